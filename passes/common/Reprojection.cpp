#include "passes/common/Reprojection.h"

#include <cmath>

namespace fp {

PreviousPixel reprojectPixel(int px,
                             int py,
                             const Vec3d& offset,
                             const Vec3d& eye,
                             const Texture* velocity,
                             const CameraView& previous) {
    if (velocity)
        return {px + 0.5 + velocity->image().plane(0).at(px, py),
                py + 0.5 + velocity->image().plane(1).at(px, py)};
    const CameraView::Projection proj = previous.projectOffset(offset, eye);
    if (proj.depth <= 0)
        return {};
    return {proj.px, proj.py};
}

PreviousPixel reprojectPixelAtDepth(const CameraView& cam,
                                    int px,
                                    int py,
                                    double depth,
                                    const Texture* velocity,
                                    const CameraView& previous) {
    const Vec3d offset = velocity ? Vec3d{} : reprojectionOffset(cam, px, py, depth);
    return reprojectPixel(px, py, offset, cam.position, velocity, previous);
}

Vec3d reprojectionOffset(const CameraView& cam, int px, int py, double depth) {
    return std::isinf(depth) ? cam.translatedFromPixel(px, py, 1.0) * 1e12
                             : cam.translatedFromPixel(px, py, depth);
}

}  // namespace fp
