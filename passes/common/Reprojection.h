#pragma once
// Where this frame's pixel was in the previous frame (reference §3.2 step 1, §6.2 temporal step
// 1): the pixel's own motion when a velocity buffer is bound, otherwise its surface projected
// through last frame's camera. A surface behind that camera was not on last frame's screen
// (§6.2 step 2: off screen ⇒ no history), whatever the projection's divide would say.
#include "passes/core/Camera.h"
#include "passes/core/Image.h"

namespace fp {

struct PreviousPixel {
    double u = -1.0, v = -1.0;  //!< continuous pixels of last frame (centres at +0.5)

    bool onScreen(Extent frame) const {
        return u >= 0 && v >= 0 && u < frame.width && v < frame.height;
    }
};

/// Last frame's position of full-resolution pixel (px, py) whose surface lies at `offset` from
/// `eye` (this frame's eye). `velocity` (X, Y in pixels) wins when bound; `previous` is then not
/// read. A point behind `previous` comes back as (−1, −1): off screen.
PreviousPixel reprojectPixel(int px,
                             int py,
                             const Vec3d& offset,
                             const Vec3d& eye,
                             const Texture* velocity,
                             const CameraView& previous);

/// The offset from the eye that pixel (px, py) at view depth `depth` reprojects: its surface, or
/// for sky (depth +∞) a far point along its ray, so that sky moves by the camera's rotation only.
Vec3d reprojectionOffset(const CameraView& cam, int px, int py, double depth);

/// reprojectPixel for pixel (px, py) of `cam` at view depth `depth` (sky: rotation only); the
/// surface is rebuilt from the depth only when no velocity is bound.
PreviousPixel reprojectPixelAtDepth(const CameraView& cam,
                                    int px,
                                    int py,
                                    double depth,
                                    const Texture* velocity,
                                    const CameraView& previous);

}  // namespace fp
