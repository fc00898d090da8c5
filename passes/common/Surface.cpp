#include "passes/common/Surface.h"

#include "passes/common/GBuffer.h"
#include "passes/core/ShadingModel.h"
#include "passes/core/Tiles.h"

#include <algorithm>

namespace fp {

Surface pixelSurface(const CameraView& cam,
                     const SurfaceInputs& in,
                     int px,
                     int py,
                     float scale,
                     NormalRead read) {
    Surface s;
    const double d = in.depth.at(px, py);
    if (!isLitSurface(d, in.shadingModel.at(px, py)))
        return s;
    const Vec3d p = cam.translatedFromPixel(px, py, d);
    s.valid = true;
    s.position = {float(p.x), float(p.y), float(p.z)};
    s.normal = gbuffer::worldNormalAt(in.normal, px, py);
    if (read == NormalRead::Normalised)
        s.normal = normalize(s.normal);
    s.radius = float(cam.pixelRadiusAtDepth(d)) * scale;
    return s;
}

SurfaceGrid::SurfaceGrid(const CameraView& cam,
                         const SurfaceInputs& in,
                         Extent grid,
                         int step,
                         NormalRead read)
    : mWidth(grid.width), mSurfaces(std::size_t(grid.width) * grid.height) {
    const int lastX = in.depth.width() - 1, lastY = in.depth.height() - 1;
    forEachTile(grid.width, grid.height, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x)
                mSurfaces[std::size_t(y) * mWidth + x] =
                    pixelSurface(cam, in, std::min(x * step, lastX), std::min(y * step, lastY),
                                 float(step), read);
    });
}

}  // namespace fp
