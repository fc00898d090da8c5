#pragma once
// The per-pixel surface that Unreal's screen-space denoiser compares neighbours with (reference
// §6.2, §6.3): the camera-relative position, the world normal and the pixel's world radius
// tan(halfFOVx)/ViewW × depth, the unit of its bilateral distances. Built once per frame (or per
// trace grid) because every tap of every filtering pass reads it again.
#include "foundation/Camera.h"
#include "foundation/HostDevice.h"
#include "foundation/Image.h"
#include "foundation/Math.h"
#include "foundation/PlaneView.h"
#include "foundation/ShadingModel.h"

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>

namespace fp {

/// 16-byte aligned, so the GPU reads a surface in two 16-byte fetches (SurfaceGridView::at).
struct alignas(16) Surface {
    bool valid = false;  //!< a lit surface (not sky, not unlit): the only pixels compared
    Vec3f position;      //!< camera-relative, scene units
    Vec3f normal;        //!< world (unit when built with NormalRead::Normalised)
    float radius = 0;    //!< pixel world radius at the grid's resolution, scene units
};

static_assert(sizeof(Surface) == 32 && offsetof(Surface, position) == 4 &&
                  offsetof(Surface, normal) == 16 && offsetof(Surface, radius) == 28,
              "SurfaceGridView::at reads a surface as two 16-byte fetches in this layout");

/// Whether the stored world normal is normalised on read. Each denoiser keeps the reading it has
/// always had (SSGI's normalises; the shadow filter's uses the GBuffer's value as stored).
enum class NormalRead { AsStored, Normalised };

/// The GBuffer planes a surface is built from.
struct SurfaceInputs {
    const Plane& depth;
    const Image& normal;
    const Plane& shadingModel;
};

/// The same planes as per-pixel code reads them, on either backend (PlaneView.h).
struct SurfaceInputsView {
    PlaneView depth, normal[3], shadingModel;
};

inline SurfaceInputsView viewOf(const SurfaceInputs& in) {
    return {viewOf(in.depth),
            {viewOf(in.normal.plane(0)), viewOf(in.normal.plane(1)), viewOf(in.normal.plane(2))},
            viewOf(in.shadingModel)};
}

/// A pixel's coordinates.
struct PixelCoord {
    int x, y;
};

/// The full-resolution pixel of a `width` × `height` frame that texel (x, y) of a grid `step`
/// pixels apart stands for: (min(x·step, W − 1), min(y·step, H − 1)) — the pixel itself at step 1,
/// the top-left pixel of its 2×2 block at step 2 (a half-resolution trace, algorithms §4.3).
FP_HD inline PixelCoord fullResPixel(int x, int y, int step, int width, int height) {
    return {x * step < width - 1 ? x * step : width - 1, y * step < height - 1 ? y * step : height - 1};
}

/// The surface at full-resolution pixel (px, py); its radius is the pixel world radius × `scale`
/// (2 when it stands for a 2×2 block of a half-resolution trace).
FP_HD inline Surface pixelSurface(const CameraView& cam,
                                  const SurfaceInputsView& in,
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
    s.normal = {in.normal[0].at(px, py), in.normal[1].at(px, py), in.normal[2].at(px, py)};
    if (read == NormalRead::Normalised)
        s.normal = normalize(s.normal);
    s.radius = float(cam.pixelRadiusAtDepth(d)) * scale;
    return s;
}

inline Surface pixelSurface(const CameraView& cam,
                            const SurfaceInputs& in,
                            int px,
                            int py,
                            float scale,
                            NormalRead read) {
    return pixelSurface(cam, viewOf(in), px, py, scale, read);
}

/// A grid of surfaces in memory of either backend: texel (x, y) stands for full-resolution pixel
/// fullResPixel(x, y, step, W, H) — the frame itself (step 1) or a half-resolution trace (step 2).
struct SurfaceGridView {
    Surface* data = nullptr;
    int width = 0, height = 0, step = 1;

    /// Texel (x, y). On the GPU as two 16-byte read-only fetches: the denoisers' gathers read a
    /// neighbour's surface at every tap, and field by field each took eight 4-byte loads.
    FP_HD Surface at(int x, int y) const {
#if defined(__CUDA_ARCH__)
        const float4* p = reinterpret_cast<const float4*>(data + (y * width + x));
        const float4 a = __ldg(p), b = __ldg(p + 1);
        Surface s;
        s.valid = (__float_as_uint(a.x) & 0xffu) != 0;
        s.position = {a.y, a.z, a.w};
        s.normal = {b.x, b.y, b.z};
        s.radius = b.w;
        return s;
#else
        return data[y * width + x];
#endif
    }
    /// Builds texel (x, y) from the GBuffer (every texel once, before any is read) and returns it.
    FP_HD Surface build(const CameraView& cam, const SurfaceInputsView& in, NormalRead read, int x,
                        int y) const {
        const PixelCoord p = fullResPixel(x, y, step, in.depth.width, in.depth.height);
        const Surface s = pixelSurface(cam, in, p.x, p.y, float(step), read);
        data[y * width + x] = s;
        return s;
    }
};

/// A SurfaceGridView's texels in host memory, built on the CPU.
class SurfaceGrid {
public:
    SurfaceGrid(const CameraView& cam,
                const SurfaceInputs& in,
                Extent grid,
                int step,
                NormalRead read);
    const Surface& at(int x, int y) const { return mSurfaces[std::size_t(y) * mWidth + x]; }
    SurfaceGridView view() { return {mSurfaces.get(), mWidth, mHeight, mStep}; }

private:
    int mWidth, mHeight, mStep;
    // Left unwritten on allocation: the tiles build every texel in parallel (a value-initialised
    // vector would first write the whole grid on one thread).
    struct RawDelete {
        void operator()(Surface* p) const { ::operator delete(p); }
    };
    static_assert(std::is_trivially_copyable_v<Surface> && std::is_trivially_destructible_v<Surface>,
                  "texels are assigned into raw storage");
    std::unique_ptr<Surface[], RawDelete> mSurfaces;
};

}  // namespace fp
