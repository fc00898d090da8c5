#include "screenspace/Reprojection.h"

namespace fp {

PreviousPixel reprojectPixel(int px,
                             int py,
                             const Vec3d& offset,
                             const Vec3d& eye,
                             const Texture* velocity,
                             const CameraView& previous) {
    return reprojectPixel(px, py, offset, eye, velocityViewOf(velocity), previous);
}

PreviousPixel reprojectPixelAtDepth(const CameraView& cam,
                                    int px,
                                    int py,
                                    double depth,
                                    const Texture* velocity,
                                    const CameraView& previous) {
    return reprojectPixelAtDepth(cam, px, py, depth, velocityViewOf(velocity), previous);
}

}  // namespace fp
