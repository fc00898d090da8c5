// ShadowLanes.h: compiled once per x86 instruction set (foreach_target.h re-includes this file);
// lanes(), setupRow and sampleRow call the widest one the CPU has. Each build runs the kernel's
// own setupPixel and sampleRay (RTShadowsKernel.h) over LaneFloat<the target's float lanes>, a
// row's neighbouring pixels a vector, inlined whole (flatten) so they compile to that
// instruction set; this file only moves pixels in and out of lanes and packs the rays traced.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/rt_shadows/ShadowLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "passes/rt_shadows/ShadowLanes.h"

#include <algorithm>

HWY_BEFORE_NAMESPACE();
namespace fp::shadow::HWY_NAMESPACE {

// One lane type per target (lanesForTarget).
constexpr int kLanesHere = lanesForTarget(int(HWY_LANES(float)));
static_assert(kLanesHere <= kMaxLanes, "a row holds whole vectors");
using T = LaneFloat<kLanesHere>;
using I = IntOf<T>;
using U = UIntOf<T>;

// Each lane's index in its vector.
constexpr int32_t kLaneIndex[kMaxLanes] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};

int lanesHere() {
    return kLanesHere;
}

__attribute__((flatten)) void setupRowHere(const RowContext& c, const RowInputs& in, RowPixels& out) {
    const int n = in.count;
    out.x0 = in.x0;
    out.count = n;

    // Whole vectors are read from the planes where they lie inside the row; a last, partial
    // vector from a zero-padded copy of the row's tail (depth 0: its lanes past the row are not
    // lit, so inactive).
    enum Input { kDepth, kNormalX, kNormalY, kNormalZ, kModel, kInputCount };
    const int whole = n / kLanesHere * kLanesHere;
    float tail[kInputCount][kMaxLanes] = {};
    const float* planes[kInputCount] = {in.depth, in.normalX, in.normalY, in.normalZ, in.model};
    for (int p = 0; p < kInputCount; ++p)
        std::copy(planes[p] + whole, planes[p] + n, tail[p]);
    // Plane p's floats from pixel i on (a vector from i stays in one part).
    auto row = [&](int p, int i) { return i < whole ? planes[p] + i : tail[p] + (i - whole); };

    for (int i = 0; i < n; i += kLanesHere) {
        const U x = U(uint32_t(in.x0 + i)) + LaneTypes<T>::indices();
        PixelOf<T> px;
        const MaskOf<T> active =
            setupPixel<T>(c, x, in.y, T::load(row(kDepth, i)), T::load(row(kModel, i)),
                          loadLanes3<T>(row(kNormalX, i), row(kNormalY, i), row(kNormalZ, i)), px);
        for (int k = 0; k < kLanesHere; ++k)
            out.active[i + k] = laneOf(active, k) ? 1 : 0;
        if (!anyLane(active))
            continue;  // nothing of this vector is read
        storeLanes3(px.p, out.px + i, out.py + i, out.pz + i);
        storeLanes3(px.n, out.nx + i, out.ny + i, out.nz + i);
        storeLanes3(px.toEye, out.ex + i, out.ey + i, out.ez + i);
        px.eyeDistance.store(out.eyeDistance + i);
        px.model.store(out.model + i);
        px.rng.store(out.rng + i);
    }
}

__attribute__((flatten)) void sampleRowHere(const RowContext& c, int stripRow, RowPixels& px,
                                            StripRays& rays) {
    const I laneIndex = I::load(kLaneIndex);
    for (int i = 0; i < px.count; i += kLanesHere) {
        const MaskOf<T> live = !(I::load(px.active + i) == 0);
        if (!anyLane(live))
            continue;
        // Lanes of inactive pixels draw their numbers too, but their streams are never read.
        PixelOf<T> p{loadLanes3<T>(px.px + i, px.py + i, px.pz + i),
                     loadLanes3<T>(px.nx + i, px.ny + i, px.nz + i),
                     loadLanes3<T>(px.ex + i, px.ey + i, px.ez + i),
                     T::load(px.eyeDistance + i),
                     I::load(px.model + i),
                     U::load(px.rng + i)};
        ShadowRayOf<T> ray{};  // (written where a lane traces)
        const MaskOf<T> traces = live & sampleRay<T>(c, p, ray);
        p.rng.store(px.rng + i);
        if (!anyLane(traces))
            continue;
        // The rays traced, in pixel order, after those of the strip's earlier pixels.
        const int k = rays.count;
        compressStore(ray.org.x, traces, rays.ox + k);
        compressStore(ray.org.y, traces, rays.oy + k);
        compressStore(ray.org.z, traces, rays.oz + k);
        compressStore(ray.dir.x, traces, rays.dx + k);
        compressStore(ray.dir.y, traces, rays.dy + k);
        compressStore(ray.dir.z, traces, rays.dz + k);
        compressStore(ray.tfar, traces, rays.tfar + k);
        rays.count += compressStore(I(ownerOf(stripRow, i)) + laneIndex, traces, rays.owner + k);
    }
}

}  // namespace fp::shadow::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::shadow {

HWY_EXPORT(lanesHere);
HWY_EXPORT(setupRowHere);
HWY_EXPORT(sampleRowHere);

int lanes() {
    return HWY_DYNAMIC_DISPATCH(lanesHere)();
}

void setupRow(const RowContext& c, const RowInputs& in, RowPixels& out) {
    HWY_DYNAMIC_DISPATCH(setupRowHere)(c, in, out);
}

void sampleRow(const RowContext& c, int stripRow, RowPixels& px, StripRays& rays) {
    HWY_DYNAMIC_DISPATCH(sampleRowHere)(c, stripRow, px, rays);
}

}  // namespace fp::shadow
#endif
