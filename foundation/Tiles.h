#pragma once
// Fixed 64×64 tiles, independent of the thread count, so anything computed per tile (and every
// per-pixel random number) is the same whatever `--threads` says (docs/design.md, Numerics and determinism).
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

namespace fp {

constexpr int kTileSize = 64;

/// A rectangle of pixels [x0, x1) × [y0, y1).
struct Tile {
    int x0, y0, x1, y1;
};

/// Runs `fn(const Tile&)` over `width × height` in 64×64 tiles on the shared oneTBB pool.
template <class Fn>
void forEachTile(int width, int height, Fn&& fn) {
    if (width <= 0 || height <= 0) return;
    const int tilesX = (width + kTileSize - 1) / kTileSize;
    const int tilesY = (height + kTileSize - 1) / kTileSize;
    tbb::parallel_for(
        tbb::blocked_range2d<int>(0, tilesY, 1, 0, tilesX, 1),
        [&](const tbb::blocked_range2d<int>& r) {
            for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
                for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) {
                    Tile t{tx * kTileSize, ty * kTileSize, 0, 0};
                    t.x1 = t.x0 + kTileSize < width ? t.x0 + kTileSize : width;
                    t.y1 = t.y0 + kTileSize < height ? t.y0 + kTileSize : height;
                    fn(t);
                }
        },
        tbb::simple_partitioner());
}

}  // namespace fp
