// DeferredLightingLanes.h: compiled once per x86 instruction set (foreach_target.h re-includes
// this file); lanes() and shadeRectDefaultLit call the widest one the CPU has. Each build is the
// kernel's rectDefaultLit over LaneFloat<the target's float lanes>, inlined whole (flatten) so it
// compiles to that instruction set; this file only moves pixels in and out of lanes.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/deferred_lighting/DeferredLightingLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "passes/deferred_lighting/DeferredLightingKernel.h"
#include "passes/deferred_lighting/DeferredLightingLanes.h"

HWY_BEFORE_NAMESPACE();
namespace fp::deferred::HWY_NAMESPACE {

// One lane type per target (lanesForTarget).
constexpr int kLanesHere = lanesForTarget(int(HWY_LANES(float)));
static_assert(kLanesHere <= kMaxLanes, "PixelLanes holds a whole vector");
using T = LaneFloat<kLanesHere>;

int lanesHere() {
    return kLanesHere;
}

__attribute__((flatten)) void shadeRect(const deferred_lighting::LightShape& light, const PixelLanes& in,
                                        LaneSums& out) {
    deferred_lighting::DefaultLitPixel<T> s;
    s.p = loadLanes3<T>(in.px, in.py, in.pz);
    s.V = loadLanes3<T>(in.vx, in.vy, in.vz);
    s.N = loadLanes3<T>(in.nx, in.ny, in.nz);
    s.diffuseColor = loadLanes3<T>(in.diffuseR, in.diffuseG, in.diffuseB);
    s.specularColor = loadLanes3<T>(in.specularR, in.specularG, in.specularB);
    s.roughness = T::load(in.roughness);
    s.surfaceShadow = T::load(in.surfaceShadow);
    s.transmissionShadow = T::load(in.transmissionShadow);
    MaskOf<T> reached;
    const Vec3T<T> sum = deferred_lighting::rectDefaultLit(light, s, reached);
    storeLanes3(sum, out.r, out.g, out.b);
    reached.store(out.reached);
}

}  // namespace fp::deferred::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::deferred {

HWY_EXPORT(lanesHere);
HWY_EXPORT(shadeRect);

int lanes() {
    return HWY_DYNAMIC_DISPATCH(lanesHere)();
}

void shadeRectDefaultLit(const deferred_lighting::LightShape& light, const PixelLanes& in, LaneSums& out) {
    HWY_DYNAMIC_DISPATCH(shadeRect)(light, in, out);
}

}  // namespace fp::deferred
#endif
