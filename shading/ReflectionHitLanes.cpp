// ReflectionHitLanes.h: compiled once per x86 instruction set (foreach_target.h re-includes this
// file); drawLightRayLanes calls the widest one the CPU has. Each build runs stratifiedSampleOf,
// sampleLightOf and lightValueOf (DirectLighting.h) over LaneFloat<the target's float lanes>, a
// wave's neighbouring hits a vector, inlined whole (flatten) so they compile to that instruction
// set; this file only moves hits in and out of lanes.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shading/ReflectionHitLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "shading/ReflectionHitLanes.h"

HWY_BEFORE_NAMESPACE();
namespace fp::reflection_hits::HWY_NAMESPACE {

// One lane type per target (lanesForTarget).
constexpr int kLanesHere = lanesForTarget(int(HWY_LANES(float)));
using T = LaneFloat<kLanesHere>;
using U = UIntOf<T>;

__attribute__((flatten)) void drawHere(const LightView* lights, int lightCount, int samples,
                                       ReflectionHitLanes& hits, SampleLanes& out) {
    int slots = 0;
    for (int l = 0; l < lightCount; ++l) slots += samplesOf(lights[l], samples);
    const int n = hits.count;
    out.stride = (n + kLanesHere - 1) / kLanesHere * kLanesHere;
    const std::size_t size = std::size_t(out.stride) * std::size_t(slots);
    for (auto* v : {&out.dx, &out.dy, &out.dz, &out.tfar, &out.lr, &out.lg, &out.lb}) v->resize(size);
    out.keep.resize(size);
    for (int i = 0; i < n; i += kLanesHere) {
        const Vec3T<T> p = loadLanes3<T>(&hits.px[i], &hits.py[i], &hits.pz[i]);
        const Vec3T<T> o = loadLanes3<T>(&hits.ox[i], &hits.oy[i], &hits.oz[i]);
        const Vec3T<T> normal = loadLanes3<T>(&hits.nx[i], &hits.ny[i], &hits.nz[i]);
        const Vec3T<T> toViewer = loadLanes3<T>(&hits.vx[i], &hits.vy[i], &hits.vz[i]);
        const Vec3T<T> diffuse = loadLanes3<T>(&hits.dr[i], &hits.dg[i], &hits.db[i]);
        const Vec3T<T> specular = loadLanes3<T>(&hits.sr[i], &hits.sg[i], &hits.sb[i]);
        const T roughness = T::load(&hits.roughness[i]);
        U rng = U::load(&hits.rng[i]);
        int slot = 0;
        for (int l = 0; l < lightCount; ++l) {
            const LightView& light = lights[l];
            const int count = samplesOf(light, samples);
            // A rect light's sample aims from the rays' origin (sampleLight).
            const Vec3T<T>& from = light.type == LightType::Rect ? o : p;
            for (int k = 0; k < count; ++k, ++slot) {
                T u(0.5f), v(0.5f);
                if (sampledAcross(light, count)) stratifiedSampleOf<T>(k, count, rng, u, v);
                const LightSampleOf<T> ls = sampleLightOf<T>(light, p, from, u, v);
                const T NoL = dot(normal, ls.L);
                const MaskOf<T> keep = ls.reaches() & !(NoL <= 0.0f);
                const Vec3T<T> value =
                    lightValueOf<T>(diffuse, specular, roughness, normal, toViewer, ls, NoL);
                const std::size_t at = std::size_t(slot) * std::size_t(out.stride) + std::size_t(i);
                for (int j = 0; j < kLanesHere; ++j)
                    out.keep[at + std::size_t(j)] = laneOf(keep, j) ? 1 : 0;
                storeLanes3(ls.shadowDir, &out.dx[at], &out.dy[at], &out.dz[at]);
                ls.shadowDistance.store(&out.tfar[at]);
                storeLanes3(value, &out.lr[at], &out.lg[at], &out.lb[at]);
            }
        }
        rng.store(&hits.rng[i]);
    }
}

}  // namespace fp::reflection_hits::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp {

namespace reflection_hits {
HWY_EXPORT(drawHere);
}  // namespace reflection_hits

void ReflectionHitLanes::resize(int n) {
    HitLanes::resize(n);
    const std::size_t padded = px.size();
    for (auto* v : {&vx, &vy, &vz, &sr, &sg, &sb, &roughness}) v->resize(padded);
}

void ReflectionHitLanes::set(std::size_t i, const SurfacePoint& s, uint32_t state) {
    HitLanes::set(i, s, state);
    vx[i] = s.toViewer.x, vy[i] = s.toViewer.y, vz[i] = s.toViewer.z;
    sr[i] = s.brdf.specularColor.x, sg[i] = s.brdf.specularColor.y, sb[i] = s.brdf.specularColor.z;
    roughness[i] = s.brdf.roughness;
}

void drawLightRayLanes(const LightView* lights, int lightCount, int samples,
                       ReflectionHitLanes& hits, SampleLanes& out) {
    HWY_DYNAMIC_DISPATCH(reflection_hits::drawHere)(lights, lightCount, samples, hits, out);
}

}  // namespace fp
#endif
