// RTReflectionsLanes.h: compiled once per x86 instruction set (foreach_target.h re-includes this
// file); drawTexelRayLanes calls the widest one the CPU has. Each build is the kernel's own
// texelRayOf over LaneFloat<the target's float lanes> (16 with AVX-512, 8 with AVX2, 4 with
// SSE4), inlined whole (flatten) so it compiles to that instruction set; this file only moves
// texels in and out of lanes.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/rt_reflections/RTReflectionsLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "passes/rt_reflections/RTReflectionsKernel.h"
#include "passes/rt_reflections/RTReflectionsLanes.h"

HWY_BEFORE_NAMESPACE();
namespace fp::rtr::HWY_NAMESPACE {

// One lane type per target (lanesForTarget).
constexpr int kLanesHere = lanesForTarget(int(HWY_LANES(float)));
using T = LaneFloat<kLanesHere>;
using U = UIntOf<T>;

__attribute__((flatten)) void drawHere(const RayBias& bias, TexelLanes& t) {
    for (int i = 0; i < t.count; i += kLanesHere) {
        PixelSurfaceOf<T> surface;
        surface.p = loadLanes3<T>(&t.px[i], &t.py[i], &t.pz[i]);
        surface.toEye = loadLanes3<T>(&t.ex[i], &t.ey[i], &t.ez[i]);
        surface.eyeDistance = T::load(&t.distance[i]);
        const Vec3T<T> N = loadLanes3<T>(&t.nx[i], &t.ny[i], &t.nz[i]);
        U rng = U::load(&t.rng[i]);
        Vec3T<T> org, L;
        texelRayOf<T>(bias, surface, N, T::load(&t.roughness[i]), rng, org, L);
        rng.store(&t.rng[i]);
        storeLanes3(org, &t.ox[i], &t.oy[i], &t.oz[i]);
        storeLanes3(L, &t.lx[i], &t.ly[i], &t.lz[i]);
    }
}

__attribute__((flatten)) int tracingHere(const Frame& f, int y, int x0, int x1, int* xs) {
    const float* depth = f.depth.data + planeIndex(0, y, f.depth.stride);
    const float* model = f.model.data + planeIndex(0, y, f.model.stride);
    const float* roughness = f.roughness.data + planeIndex(0, y, f.roughness.stride);
    int n = 0, x = x0;
    for (; x + kLanesHere <= x1; x += kLanesHere)
        n += compressStore(LaneTypes<T>::indices() + uint32_t(x),
                           tracesOf(T::load(depth + x), T::load(model + x), T::load(roughness + x),
                                    f.setup.maxRoughness),
                           xs + n);
    for (; x < x1; ++x)  // the row's tail, a texel at a time
        if (tracesOf(depth[x], model[x], roughness[x], f.setup.maxRoughness)) xs[n++] = x;
    return n;
}

}  // namespace fp::rtr::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::rtr {

HWY_EXPORT(drawHere);
HWY_EXPORT(tracingHere);

void TexelLanes::resize(int n) {
    count = n;
    // Whole vectors of the widest lanes any build has (16), the tail's lanes never read.
    const std::size_t padded = std::size_t((n + 15) / 16 * 16);
    for (auto* v : {&px, &py, &pz, &ex, &ey, &ez, &distance, &nx, &ny, &nz, &roughness, &ox, &oy,
                    &oz, &lx, &ly, &lz})
        v->resize(padded);
    rng.resize(padded);
}

void drawTexelRayLanes(const RayBias& bias, TexelLanes& texels) {
    HWY_DYNAMIC_DISPATCH(drawHere)(bias, texels);
}

int tracingTexelsOfRow(const Frame& f, int y, int x0, int x1, int* xs) {
    return HWY_DYNAMIC_DISPATCH(tracingHere)(f, y, x0, x1, xs);
}

}  // namespace fp::rtr
#endif
