#include "screenspace/Surface.h"

#include "foundation/Tiles.h"

namespace fp {

SurfaceGrid::SurfaceGrid(const CameraView& cam,
                         const SurfaceInputs& in,
                         Extent grid,
                         int step,
                         NormalRead read)
    : mWidth(grid.width),
      mHeight(grid.height),
      mStep(step),
      mSurfaces(static_cast<Surface*>(
          ::operator new(std::size_t(grid.width) * grid.height * sizeof(Surface)))) {
    const SurfaceGridView v = view();
    const SurfaceInputsView inputs = viewOf(in);
    forEachTile(grid.width, grid.height, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x)
                v.build(cam, inputs, read, x, y);
    });
}

}  // namespace fp
