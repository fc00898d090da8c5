#pragma once
// Camera motion vectors per pixel, written once for both backends: CameraVelocityPass::execute
// runs it with CpuPixels, CameraVelocityPass.cu with CudaPixels.
#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "framework/Pass.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Reprojection.h"

#include <limits>

namespace fp::camera_velocity {

inline constexpr const char* kVelocity = "velocity";

/// Everything one frame's pixels read and write.
struct Frame {
    CameraView cam, previous;
    PlaneView depth;
    PlaneSpan velocity[2];
    double sky;  //!< depths at or beyond this move as sky (rotation only)
};

/// Pixel (x, y): the pixels from its centre to its surface on last frame's screen.
FP_HD inline void velocityPixel(const Frame& f, int x, int y) {
    const double d = f.depth.at(x, y) >= f.sky ? std::numeric_limits<double>::infinity()
                                               : double(f.depth.at(x, y));
    const PreviousPixel p = reprojectPixelAtDepth(f.cam, x, y, d, VelocityView{}, f.previous);
    f.velocity[0].at(x, y) = float(p.u - (x + 0.5));
    f.velocity[1].at(x, y) = float(p.v - (y + 0.5));
}

/// The whole pass through `ports` on `pixels`, its work reported to `ctx`.
template <class Ports, class Pixels>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, float skyDistance) {
    const FrameInfo& frame = ctx.frame();
    FP_CHECK(frame.camera.previous,
             "frame {}: camera_velocity needs last frame's camera (a 'previous' camera in the "
             "header or sidecar)",
             frame.number);
    Frame f{};
    f.cam = frame.camera.current;
    f.previous = *frame.camera.previous;
    f.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    auto& velocity = ports.overwrite(kVelocity, {frame.extent});
    for (int c = 0; c < 2; ++c) f.velocity[c] = spanOf(velocity.image().plane(c));
    f.sky = skyDistance > 0.0f ? double(skyDistance) : std::numeric_limits<double>::infinity();
    pixels.template forEach<0>(
        frame.extent.width, frame.extent.height,
        [=] FP_HD(int x, int y, WorkCounts<0>&) { velocityPixel(f, x, y); }, "camera_velocity");
    ctx.addWork("pixels", uint64_t(frame.extent.width) * uint64_t(frame.extent.height));
}

}  // namespace fp::camera_velocity
