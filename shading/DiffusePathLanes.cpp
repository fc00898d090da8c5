// DiffusePathLanes.h: compiled once per x86 instruction set (foreach_target.h re-includes this
// file); drawLightSampleLanes calls the widest one the CPU has. Each build runs drawLightSample
// (DiffusePaths.h) and sampleLightOf (DirectLighting.h) over LaneFloat<the target's float lanes>,
// a step's neighbouring hits a vector, inlined whole (flatten) so they compile to that
// instruction set; this file only moves hits in and out of lanes.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shading/DiffusePathLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "shading/DiffusePathLanes.h"
#include "shading/DiffusePaths.h"

HWY_BEFORE_NAMESPACE();
namespace fp::paths::HWY_NAMESPACE {

// One lane type per target (lanesForTarget).
constexpr int kLanesHere = lanesForTarget(int(HWY_LANES(float)));
using T = LaneFloat<kLanesHere>;
using U = UIntOf<T>;

__attribute__((flatten)) void drawHere(const LightView* lights, int lightCount, int nee,
                                       HitLanes& hits, SampleLanes& out) {
    // Each lane takes the light it picked: the first light's sample, replaced where a lane picked
    // another (only the lights some lane of the vector picked are sampled).
    auto sampleAt = [&](const Vec3T<T>& p, const Vec3T<T>& o, T index, T u, T v) {
        LightSampleOf<T> ls = sampleLightOf<T>(lights[0], p, o, u, v);
        for (int l = 1; l < lightCount; ++l) {
            const MaskOf<T> mine = index == T(float(l));
            if (!anyLane(mine)) continue;
            const LightSampleOf<T> other = sampleLightOf<T>(lights[l], p, o, u, v);
            ls.L = ifThenElse(mine, other.L, ls.L);
            ls.irradiance = ifThenElse(mine, other.irradiance, ls.irradiance);
            ls.shadowDir = ifThenElse(mine, other.shadowDir, ls.shadowDir);
            ls.shadowDistance = ifThenElse(mine, other.shadowDistance, ls.shadowDistance);
        }
        return ls;
    };
    const int n = hits.count;
    out.stride = (n + kLanesHere - 1) / kLanesHere * kLanesHere;
    const std::size_t size = std::size_t(out.stride) * std::size_t(nee);
    for (auto* v : {&out.dx, &out.dy, &out.dz, &out.tfar, &out.lr, &out.lg, &out.lb}) v->resize(size);
    out.keep.resize(size);
    for (int i = 0; i < n; i += kLanesHere) {
        const Vec3T<T> p = loadLanes3<T>(&hits.px[i], &hits.py[i], &hits.pz[i]);
        const Vec3T<T> o = loadLanes3<T>(&hits.ox[i], &hits.oy[i], &hits.oz[i]);
        const Vec3T<T> normal = loadLanes3<T>(&hits.nx[i], &hits.ny[i], &hits.nz[i]);
        const Vec3T<T> diffuse = loadLanes3<T>(&hits.dr[i], &hits.dg[i], &hits.db[i]);
        U rng = U::load(&hits.rng[i]);
        for (int k = 0; k < nee; ++k) {
            LightSampleOf<T> ls;
            MaskOf<T> keep;
            Vec3T<T> lit;
            drawLightSample<T>(lightCount, rng, normal, diffuse,
                               [&](T index, T u, T v) { return sampleAt(p, o, index, u, v); }, ls,
                               keep, lit);
            const std::size_t at = std::size_t(k) * std::size_t(out.stride) + std::size_t(i);
            for (int j = 0; j < kLanesHere; ++j) out.keep[at + std::size_t(j)] = laneOf(keep, j) ? 1 : 0;
            storeLanes3(ls.shadowDir, &out.dx[at], &out.dy[at], &out.dz[at]);
            ls.shadowDistance.store(&out.tfar[at]);
            storeLanes3(lit, &out.lr[at], &out.lg[at], &out.lb[at]);
        }
        rng.store(&hits.rng[i]);
    }
}

}  // namespace fp::paths::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp {

namespace paths {
HWY_EXPORT(drawHere);
}  // namespace paths

void HitLanes::resize(int n) {
    count = n;
    // Whole vectors of the widest lanes any build has (16), the tail's lanes never read.
    const std::size_t padded = std::size_t((n + 15) / 16 * 16);
    for (auto* v : {&px, &py, &pz, &ox, &oy, &oz, &nx, &ny, &nz, &dr, &dg, &db}) v->resize(padded);
    rng.resize(padded);
}

void HitLanes::set(std::size_t i, const SurfacePoint& s, uint32_t state) {
    const Vec3f org = s.rayOrigin();
    px[i] = s.position.x, py[i] = s.position.y, pz[i] = s.position.z;
    ox[i] = org.x, oy[i] = org.y, oz[i] = org.z;
    nx[i] = s.normal.x, ny[i] = s.normal.y, nz[i] = s.normal.z;
    dr[i] = s.brdf.diffuseColor.x, dg[i] = s.brdf.diffuseColor.y, db[i] = s.brdf.diffuseColor.z;
    rng[i] = state;
}

void drawLightSampleLanes(const LightView* lights, int lightCount, int nee, HitLanes& hits,
                          SampleLanes& out) {
    HWY_DYNAMIC_DISPATCH(paths::drawHere)(lights, lightCount, nee, hits, out);
}

}  // namespace fp
#endif
