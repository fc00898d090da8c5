#pragma once
// The per-pixel surface that Unreal's screen-space denoiser compares neighbours with (reference
// §6.2, §6.3): the camera-relative position, the world normal and the pixel's world radius
// tan(halfFOVx)/ViewW × depth, the unit of its bilateral distances. Built once per frame (or per
// trace grid) because every tap of every filtering pass reads it again.
#include "passes/core/Camera.h"
#include "passes/core/Image.h"
#include "passes/core/Math.h"

#include <cstddef>
#include <vector>

namespace fp {

struct Surface {
    bool valid = false;  //!< a lit surface (not sky, not unlit): the only pixels compared
    Vec3f position;      //!< camera-relative, scene units
    Vec3f normal;        //!< world (unit when built with NormalRead::Normalised)
    float radius = 0;    //!< pixel world radius at the grid's resolution, scene units
};

/// Whether the stored world normal is normalised on read. Each denoiser keeps the reading it has
/// always had (SSGI's normalises; the shadow filter's uses the GBuffer's value as stored).
enum class NormalRead { AsStored, Normalised };

/// The GBuffer planes a surface is built from.
struct SurfaceInputs {
    const Plane& depth;
    const Image& normal;
    const Plane& shadingModel;
};

/// The surface at full-resolution pixel (px, py); its radius is the pixel world radius × `scale`
/// (2 when it stands for a 2×2 block of a half-resolution trace).
Surface pixelSurface(const CameraView& cam,
                     const SurfaceInputs& in,
                     int px,
                     int py,
                     float scale,
                     NormalRead read);

/// The surfaces of a grid whose texel (x, y) stands for full-resolution pixel
/// (min(x·step, W − 1), min(y·step, H − 1)): the frame itself (step 1) or a half-resolution trace
/// (step 2, the top-left pixel of each 2×2 block).
class SurfaceGrid {
public:
    SurfaceGrid(const CameraView& cam,
                const SurfaceInputs& in,
                Extent grid,
                int step,
                NormalRead read);
    const Surface& at(int x, int y) const { return mSurfaces[std::size_t(y) * mWidth + x]; }

private:
    int mWidth;
    std::vector<Surface> mSurfaces;
};

}  // namespace fp
