#pragma once
// Where this frame's pixel was in the previous frame (algorithms §3.2 step 1, §6.2 temporal step
// 1): the pixel's own motion when a velocity buffer is bound, otherwise its surface projected
// through last frame's camera. A surface behind that camera was not on last frame's screen
// (§6.2 step 2: off screen ⇒ no history), whatever the projection's divide would say.
#include "foundation/Camera.h"
#include "foundation/HostDevice.h"
#include "foundation/Image.h"
#include "foundation/PlaneView.h"

#include <cmath>

namespace fp {

/// Screen-edge fade at screen position (sx, sy) ∈ [−1, 1]² (algorithms §3.2 step 7; SSR's hits too,
/// §5.4): 1 inside 80 % of the screen, 0 beyond it.
FP_HD inline float vignette(float sx, float sy) {
    const float cx = saturate(std::fabs(sx) * 5.0f - 4.0f);
    const float cy = saturate(std::fabs(sy) * 5.0f - 4.0f);
    return saturate(1.0f - (cx * cx + cy * cy));
}

struct PreviousPixel {
    double u = -1.0, v = -1.0;  //!< continuous pixels of last frame (centres at +0.5)

    FP_HD bool onScreen(Extent frame) const {
        return u >= 0 && v >= 0 && u < frame.width && v < frame.height;
    }
};

/// A bound velocity buffer's X and Y planes, as per-pixel code reads them (null when unbound).
struct VelocityView {
    PlaneView x, y;
    FP_HD bool bound() const { return x.data != nullptr; }
};

/// The velocity view of a host Texture or DeviceTexture (nullptr: unbound).
template <class TextureT>
VelocityView velocityViewOf(const TextureT* velocity) {
    if (!velocity)
        return {};
    return {viewOf(velocity->image().plane(0)), viewOf(velocity->image().plane(1))};
}

/// Last frame's position of full-resolution pixel (px, py) whose surface lies at `offset` from
/// `eye` (this frame's eye). `velocity` (X, Y in pixels) wins when bound; `previous` is then not
/// read. A point behind `previous` comes back as (−1, −1): off screen.
FP_HD inline PreviousPixel reprojectPixel(int px,
                                          int py,
                                          const Vec3d& offset,
                                          const Vec3d& eye,
                                          const VelocityView& velocity,
                                          const CameraView& previous) {
    if (velocity.bound())
        return {px + 0.5 + velocity.x.at(px, py), py + 0.5 + velocity.y.at(px, py)};
    const CameraView::Projection proj = previous.projectOffset(offset, eye);
    if (proj.depth <= 0)
        return {};
    return {proj.px, proj.py};
}

/// The offset from the eye that pixel (px, py) at view depth `depth` reprojects: its surface, or
/// for sky (depth +∞) a far point along its ray, so that sky moves by the camera's rotation only.
FP_HD inline Vec3d reprojectionOffset(const CameraView& cam, int px, int py, double depth) {
    return std::isinf(depth) ? cam.translatedFromPixel(px, py, 1.0) * 1e12
                             : cam.translatedFromPixel(px, py, depth);
}

/// reprojectPixel for pixel (px, py) of `cam` at view depth `depth` (sky: rotation only); the
/// surface is rebuilt from the depth only when no velocity is bound.
FP_HD inline PreviousPixel reprojectPixelAtDepth(const CameraView& cam,
                                                 int px,
                                                 int py,
                                                 double depth,
                                                 const VelocityView& velocity,
                                                 const CameraView& previous) {
    const Vec3d offset = velocity.bound() ? Vec3d{} : reprojectionOffset(cam, px, py, depth);
    return reprojectPixel(px, py, offset, cam.position, velocity, previous);
}

/// The same with a host velocity Texture (nullptr: unbound).
PreviousPixel reprojectPixel(int px,
                             int py,
                             const Vec3d& offset,
                             const Vec3d& eye,
                             const Texture* velocity,
                             const CameraView& previous);

/// The same with a host velocity Texture (nullptr: unbound).
PreviousPixel reprojectPixelAtDepth(const CameraView& cam,
                                    int px,
                                    int py,
                                    double depth,
                                    const Texture* velocity,
                                    const CameraView& previous);

}  // namespace fp
