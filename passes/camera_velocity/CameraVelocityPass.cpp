#include "passes/camera_velocity/CameraVelocityPass.h"

#include "screenspace/GBuffer.h"
#include "screenspace/Reprojection.h"
#include "foundation/Error.h"
#include "foundation/Tiles.h"

#include <cmath>
#include <limits>

namespace fp {

namespace {
constexpr const char* kVelocity = "velocity";
}  // namespace

ParamSpec<CameraVelocityParams> CameraVelocityPass::paramSpec() {
    ParamSpec<CameraVelocityParams> s;
    s.add("skyDistance", &Params::skyDistance,
          "depths at or beyond this are sky and move by the camera's rotation only, scene units; "
          "0 = only +inf")
        .range(0.0, 1e30);
    return s;
}

PassIO CameraVelocityPass::describe() const {
    PassIO io;
    io.inputs = {gbuffer::depthInput()};
    io.outputs = {{.name = kVelocity,
                   .channels = {"X", "Y"},
                   .doc = "pixels from this pixel's centre to its surface on last frame's screen "
                          "(+Y down), as the capture's Velocity; a surface behind last frame's "
                          "camera points off screen"}};
    io.needsCamera = true;
    return io;
}

void CameraVelocityPass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    FP_CHECK(frame.camera.previous,
             "frame {}: camera_velocity needs last frame's camera (a 'previous' camera in the "
             "header or sidecar)",
             frame.number);
    const CameraView& cam = frame.camera.current;
    const CameraView& prev = *frame.camera.previous;
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    Image& velocity = ctx.output(kVelocity, {frame.extent}).image();
    const double sky = mParams.skyDistance > 0.0f ? double(mParams.skyDistance)
                                                  : std::numeric_limits<double>::infinity();
    forEachTile(frame.extent.width, frame.extent.height, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const double d = depth.at(x, y) >= sky ? std::numeric_limits<double>::infinity()
                                                       : double(depth.at(x, y));
                const PreviousPixel p = reprojectPixelAtDepth(cam, x, y, d, nullptr, prev);
                velocity.plane(0).at(x, y) = float(p.u - (x + 0.5));
                velocity.plane(1).at(x, y) = float(p.v - (y + 0.5));
            }
        ctx.addWork("pixels", uint64_t(t.x1 - t.x0) * (t.y1 - t.y0));
    });
}

}  // namespace fp
