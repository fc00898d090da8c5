// AmbientOcclusionLanes.h: compiled once per x86 instruction set (foreach_target.h re-includes
// this file); lanes(), setupRow and sampleRow call the widest one the CPU has. Each build runs the
// kernel's own setupPixel and sampleRay (RTAmbientOcclusionKernel.h) over LaneFloat<the target's
// float lanes>, a row's neighbouring pixels a vector, inlined whole (flatten) so they compile to
// that instruction set; this file only moves pixels in and out of lanes.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/rt_ambient_occlusion/AmbientOcclusionLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "passes/rt_ambient_occlusion/AmbientOcclusionLanes.h"

#include <algorithm>

HWY_BEFORE_NAMESPACE();
namespace fp::rtao::HWY_NAMESPACE {

// One lane type per target (lanesForTarget).
constexpr int kLanesHere = lanesForTarget(int(HWY_LANES(float)));
static_assert(kLanesHere <= kMaxLanes, "a row holds whole vectors");
using T = LaneFloat<kLanesHere>;
using U = UIntOf<T>;

int lanesHere() {
    return kLanesHere;
}

__attribute__((flatten)) void setupRowHere(const FrameSetup& s, const RowInputs& in, RowPixels& out) {
    const int n = in.count;
    out.count = n;
    // The row's planes and its neighbours' depths from x0 − 1 on, padded to whole vectors, 0
    // beyond the image's edges (a neighbour there has no surface; a pixel there is not lit).
    enum Input { kDepth, kRight, kLeft, kBelow, kAbove, kModel, kNormalX, kNormalY, kNormalZ, kInputCount };
    float rows[kInputCount][kRowCapacity];
    const int padded = (n + kLanesHere - 1) / kLanesHere * kLanesHere;
    // dst[i] = p(from + i, y) for i in [0, padded), 0 outside the plane: one copy of the part
    // inside, zeros around it.
    auto copyRow = [&](float* dst, const PlaneView& p, int from, int y) {
        int lo = 0, hi = 0;
        if (y >= 0 && y < p.height) {
            lo = std::clamp(-from, 0, padded);
            hi = std::clamp(p.width - from, lo, padded);
            const float* row = p.data + std::ptrdiff_t(y) * p.stride + from;
            std::copy(row + lo, row + hi, dst + lo);
        }
        std::fill(dst, dst + lo, 0.0f);
        std::fill(dst + hi, dst + padded, 0.0f);
    };
    copyRow(rows[kDepth], in.depth, in.x0, in.y);
    std::fill(rows[kDepth] + n, rows[kDepth] + padded, 0.0f);  // past the row: not lit
    copyRow(rows[kRight], in.depth, in.x0 + 1, in.y);
    copyRow(rows[kLeft], in.depth, in.x0 - 1, in.y);
    copyRow(rows[kBelow], in.depth, in.x0, in.y + 1);
    copyRow(rows[kAbove], in.depth, in.x0, in.y - 1);
    copyRow(rows[kModel], in.model, in.x0, in.y);
    for (int c = 0; c < 3; ++c)
        copyRow(rows[kNormalX + c], in.normal[c], in.x0, in.y);
    for (int i = 0; i < n; i += kLanesHere) {
        const U x = U(uint32_t(in.x0 + i)) + LaneTypes<T>::indices();
        const NeighbourDepths<T> around{T::load(rows[kRight] + i), T::load(rows[kLeft] + i),
                                        T::load(rows[kBelow] + i), T::load(rows[kAbove] + i)};
        PixelOf<T> px{};  // (written where a lane is lit)
        const MaskOf<T> active = setupPixel<T>(
            s, x, in.y, T::load(rows[kDepth] + i), T::load(rows[kModel] + i),
            loadLanes3<T>(rows[kNormalX] + i, rows[kNormalY] + i, rows[kNormalZ] + i), around, px);
        for (int k = 0; k < kLanesHere; ++k)
            out.active[i + k] = laneOf(active, k) ? 1 : 0;
        if (!anyLane(active))
            continue;  // nothing of this vector is read
        storeLanes3(px.p, out.px + i, out.py + i, out.pz + i);
        storeLanes3(px.shading, out.sx + i, out.sy + i, out.sz + i);
        storeLanes3(px.geometric, out.gx + i, out.gy + i, out.gz + i);
        storeLanes3(px.tangent, out.tx + i, out.ty + i, out.tz + i);
        storeLanes3(px.bitangent, out.bx + i, out.by + i, out.bz + i);
        storeLanes3(px.toEye, out.ex + i, out.ey + i, out.ez + i);
        px.eyeDistance.store(out.eyeDistance + i);
        px.shadingDotGeometric.store(out.overlap + i);
        px.rng.store(out.rng + i);
    }
}

__attribute__((flatten)) void sampleRowHere(const FrameSetup& s, RowPixels& px, RowRays& rays) {
    for (int i = 0; i < px.count; i += kLanesHere) {
        if (!anyLane(!(IntOf<T>::load(px.active + i) == 0)))
            continue;
        // Lanes of inactive pixels draw their numbers too, but their streams are never read.
        PixelOf<T> p{loadLanes3<T>(px.px + i, px.py + i, px.pz + i),
                     loadLanes3<T>(px.sx + i, px.sy + i, px.sz + i),
                     loadLanes3<T>(px.gx + i, px.gy + i, px.gz + i),
                     loadLanes3<T>(px.tx + i, px.ty + i, px.tz + i),
                     loadLanes3<T>(px.bx + i, px.by + i, px.bz + i),
                     loadLanes3<T>(px.ex + i, px.ey + i, px.ez + i),
                     T::load(px.eyeDistance + i),
                     T::load(px.overlap + i),
                     U::load(px.rng + i)};
        const AoRayOf<T> ray = sampleRay<T>(s, p);
        p.rng.store(px.rng + i);
        storeLanes3(ray.org, rays.ox + i, rays.oy + i, rays.oz + i);
        storeLanes3(ray.dir, rays.dx + i, rays.dy + i, rays.dz + i);
        ray.weight.store(rays.weight + i);
    }
}

}  // namespace fp::rtao::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::rtao {

HWY_EXPORT(lanesHere);
HWY_EXPORT(setupRowHere);
HWY_EXPORT(sampleRowHere);

int lanes() {
    return HWY_DYNAMIC_DISPATCH(lanesHere)();
}

void setupRow(const FrameSetup& s, const RowInputs& in, RowPixels& out) {
    HWY_DYNAMIC_DISPATCH(setupRowHere)(s, in, out);
}

void sampleRow(const FrameSetup& s, RowPixels& px, RowRays& rays) {
    HWY_DYNAMIC_DISPATCH(sampleRowHere)(s, px, rays);
}

}  // namespace fp::rtao
#endif
