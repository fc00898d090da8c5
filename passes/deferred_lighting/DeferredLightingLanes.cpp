// DeferredLightingLanes.h: compiled once per x86 instruction set (foreach_target.h re-includes
// this file); lanes() and shadeRectDefaultLit call the widest one the CPU has.
//
// Each lane repeats, operation for operation, what DeferredLightingKernel.h's forEachIncoming (rect
// branch) and shadePixel do with ShadingModelBxDF.h's default-lit lobe and BRDF.h's terms:
// the same products and sums in the same order, divisions where they divide, std::min/max/clamp's
// NaN rules (LaneMath.h). A grid point behind the emitter is left out of a lane's sum as the
// scalar loop leaves it out of its list.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/deferred_lighting/DeferredLightingLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "screenspace/LaneMath.h"
#include "passes/deferred_lighting/DeferredLightingLanes.h"
#include "shading/BRDF.h"

HWY_BEFORE_NAMESPACE();
namespace fp::deferred::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using fp::HWY_NAMESPACE::clampLike;
using fp::HWY_NAMESPACE::maxLike;

using D = hn::ScalableTag<float>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;
static_assert(HWY_MAX_BYTES / sizeof(float) <= kMaxLanes, "PixelLanes holds a whole vector");

using V3 = fp::HWY_NAMESPACE::Vec3Lanes<V>;
using fp::HWY_NAMESPACE::dot3;
using fp::HWY_NAMESPACE::normalize3;

HWY_INLINE V3 load3(const float* x, const float* y, const float* z) {
    return fp::HWY_NAMESPACE::load3(D(), x, y, z);
}

int lanesHere() {
    return int(hn::Lanes(D()));
}

// A vector of pixels as the default-lit lobe sees them, with what the lobe computes the same way
// for every direction: NoV, a2 = roughness⁴ (pow4 of the clamped roughness), √a2 and Schlick's 2%
// cut-off.
struct Surfaces {
    V3 view, n, diffuseColor, f0;
    V surfaceShadow, NoV, a2, a, cut;
    V transmission;  // a default-lit pixel's transmission term: 0, scaled by its shadow all the same

    explicit Surfaces(const PixelLanes& in) {
        const D d;
        const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
        view = load3(in.vx, in.vy, in.vz);
        n = load3(in.nx, in.ny, in.nz);
        diffuseColor = load3(in.diffuseR, in.diffuseG, in.diffuseB);
        f0 = load3(in.specularR, in.specularG, in.specularB);
        surfaceShadow = hn::LoadU(d, in.surfaceShadow);
        NoV = maxLike(dot3(n, view), hn::Set(d, 1e-4f));
        const V r = maxLike(hn::LoadU(d, in.roughness), hn::Set(d, kMinLightRoughness));
        const V r2 = r * r;
        a2 = r2 * r2;
        a = hn::Sqrt(a2);
        cut = clampLike(hn::Set(d, 50.0f) * f0.y, zero, one);
        transmission = zero * hn::LoadU(d, in.transmissionShadow);
    }

    // shadePixel's term for unit direction L bringing `falloff`: geometryOf, defaultLit
    // (Lambert and schlickF × ggxD × smithJointApproxVis × NoL), then
    // ((diffuse + specular) · surface shadow + transmission · its shadow) · falloff.
    HWY_INLINE V3 term(const V3& L, const V3& falloff) const {
        const D d;
        const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
        const V NoL = dot3(n, L);
        const V3 H = normalize3(V3{view.x + L.x, view.y + L.y, view.z + L.z});
        const V NoH = clampLike(dot3(n, H), zero, one);
        const V VoH = clampLike(dot3(view, H), zero, one);
        const M lit = hn::Not(NoL <= zero);
        const V diffuseScale = NoL / hn::Set(d, kPiF);
        const V x = one - clampLike(VoH, zero, one);
        const V x2 = x * x;
        const V fc = x2 * x2 * x;
        const V cutFc = cut * fc, oneMinusFc = one - fc;
        const V dd = (NoH * a2 - NoH) * NoH + one;
        const V ggx = a2 / (hn::Set(d, kPiF) * dd * dd);
        const V visV = NoL * (NoV * (one - a) + a);
        const V visL = NoV * (NoL * (one - a) + a);
        const V vis = hn::Set(d, 0.5f) / maxLike(visV + visL, hn::Set(d, 1e-8f));
        const V lobe = ggx * vis * NoL;
        const auto channel = [&](V diffuse, V specular, V light) {
            const V dTerm = hn::IfThenElseZero(lit, diffuse * diffuseScale);
            const V sTerm = hn::IfThenElseZero(lit, (cutFc + specular * oneMinusFc) * lobe);
            return ((dTerm + sTerm) * surfaceShadow + transmission) * light;
        };
        return {channel(diffuseColor.x, f0.x, falloff.x), channel(diffuseColor.y, f0.y, falloff.y),
                channel(diffuseColor.z, f0.z, falloff.z)};
    }
};

void store3(const V3& v, LaneSums& out) {
    const D d;
    hn::StoreU(v.x, d, out.r);
    hn::StoreU(v.y, d, out.g);
    hn::StoreU(v.z, d, out.b);
}

void shadeRect(const RectGrid& grid, const PixelLanes& in, LaneSums& out) {
    const D d;
    const V zero = hn::Zero(d);
    const V3 p = load3(in.px, in.py, in.pz);
    const Surfaces surfaces(in);
    V3 sum{zero, zero, zero};
    M reached = hn::FirstN(d, 0);
    const V3 nl{hn::Set(d, grid.normal.x), hn::Set(d, grid.normal.y), hn::Set(d, grid.normal.z)};
    const V cellArea = hn::Set(d, grid.cellArea);
    for (const Vec3f& q : grid.points) {
        // forEachIncoming: the direction to the point and its unshadowed irradiance; a point behind
        // the emitter is left out.
        const V3 toPoint{hn::Set(d, q.x) - p.x, hn::Set(d, q.y) - p.y, hn::Set(d, q.z) - p.z};
        const V dist2 = dot3(toPoint, toPoint);
        const V dist = hn::Sqrt(dist2);
        const V3 L{toPoint.x / dist, toPoint.y / dist, toPoint.z / dist};
        const V cosL = hn::Neg(dot3(L, nl));
        const M inFront = hn::Not(cosL <= zero);
        const V f = cosL * cellArea / dist2;
        const V3 falloff{hn::Set(d, grid.color.x) * f, hn::Set(d, grid.color.y) * f,
                         hn::Set(d, grid.color.z) * f};
        const V3 t = surfaces.term(L, falloff);
        sum = {hn::IfThenElse(inFront, sum.x + t.x, sum.x),
               hn::IfThenElse(inFront, sum.y + t.y, sum.y),
               hn::IfThenElse(inFront, sum.z + t.z, sum.z)};
        reached = hn::Or(reached, inFront);
    }
    store3(sum, out);
    HWY_ALIGN float reachedLanes[kMaxLanes] = {};  // lanes past the vector's stay "not reached"
    hn::StoreU(hn::IfThenElseZero(reached, hn::Set(d, 1.0f)), d, reachedLanes);
    for (int i = 0; i < in.count; ++i)
        out.reached[i] = reachedLanes[i] != 0.0f;
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

void shadeRectDefaultLit(const RectGrid& grid, const PixelLanes& in, LaneSums& out) {
    HWY_DYNAMIC_DISPATCH(shadeRect)(grid, in, out);
}

}  // namespace fp::deferred
#endif
