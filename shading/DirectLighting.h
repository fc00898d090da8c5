#pragma once
// Direct lighting of one surface point by every light of the scene, with ray-traced visibility.
// Point/spot/directional lights give their exact unshadowed irradiance (I·cosθ/r², E·cosθ) and
// sample their extent (sphere radius, source angle) only for the shadow; rect lights are
// integrated by area sampling. The per-light sample is public so the reference tracer can
// measure each light's visibility with the same geometry.
#include "foundation/Bvh.h"
#include "foundation/HostDevice.h"
#include "foundation/RayScene.h"
#include "foundation/Random.h"
#include "foundation/Sampling.h"
#include "foundation/SinCos.h"
#include "shading/BRDF.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace fp {

struct SurfacePoint {
    Vec3f position;         //!< relative to the RayScene origin
    Vec3f normal;           //!< shading normal, facing the viewer
    Vec3f geometricNormal;  //!< facing the viewer
    Vec3f toViewer;         //!< unit V
    SurfaceBRDF brdf;
    Vec3f emission;

    /// Where rays leave the surface. The step is along the geometric normal *and* back towards
    /// the viewer: the normal alone keeps a point on a concave edge on the other surface's plane
    /// (or behind it, after rounding), where half its rays meet that surface at t ≈ 0 or pass
    /// through it; every surface the arriving ray could have hit faces the viewer, so the step
    /// back puts the origin in front of both (TruthTests: AO at a concave edge).
    FP_HD Vec3f rayOrigin() const { return offsetRayOrigin(position, geometricNormal + toViewer); }
};

/// The shading point of org + t·dir on a surface of geometric normal `ng` and shading normal `n`
/// (either side); both normals are turned to face the ray (surfaces are two-sided, as the
/// capture's GBuffer sees them).
FP_HD inline SurfacePoint surfacePoint(Vec3f ng, Vec3f n, const BvhMaterial& m, const Vec3f& org,
                                       const Vec3f& dir, float t) {
    if (dot(ng, dir) > 0.0f) ng = -ng;
    if (dot(n, ng) < 0.0f) n = -n;
    return {org + dir * t, n, ng, -dir,
            SurfaceBRDF::fromMaterial(m.baseColor, m.metallic, m.specular, m.roughness),
            m.emission};
}

/// The shading point of a hit of the ray org + t·dir (Embree's), its emission the material's.
/// (Inline: a wave of paths fills its hits' records in place, where a call returned each through
/// the stack.)
inline SurfacePoint surfaceAt(const RayScene& scene, const RayHit& hit, const Vec3f& org,
                              const Vec3f& dir) {
    const Material& m = scene.material(hit);
    return surfacePoint(hit.geometricNormal, scene.shadingNormal(hit),
                        {m.baseColor, m.metallic, m.specular, m.roughness, m.emission}, org, dir,
                        hit.t);
}

/// The shading point of a closest hit through framepass's BVH (Bvh.h), on either backend: the
/// geometric normal of the triangle as stored, the vertex normals interpolated at the traversal's
/// barycentrics (RayScene::shadingNormal's rule), the emission it sends other surfaces (none
/// from a light's visible shape: Scene::emissionTowardsSurfaces).
FP_HD inline SurfacePoint surfaceAt(const BvhView& bvh, const BvhHit& hit, const Vec3f& org,
                                    const Vec3f& dir) {
    const BvhTriangle tri = bvh_detail::loadTriangle(bvh.triangles + hit.triangle);
    const Vec3f ng = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    const BvhShading& sh = bvh.shading[hit.triangle];
    float u, v;
    hitBarycentrics(bvh, hit, org, dir, u, v);
    const float w = 1.0f - u - v;
    const Vec3f n = sh.smooth ? interpolatedNormal(sh.n0, sh.n1, sh.n2, u, v, ng) : ng;
    SurfacePoint s = surfacePoint(ng, n, bvh.materials[sh.material], org, dir, hit.t);
    // The point from the triangle's own corners, not org + t·dir: the watertight test's distance
    // can be some 10⁻⁵ off along a grazing ray, enough to put the point behind the surface
    // (where rayOrigin()'s step no longer clears it and the hit shadows itself); the corners'
    // weighted sum lies on the triangle to within their own rounding (Wächter and Binder).
    s.position = tri.v0 * w + tri.v1 * u + tri.v2 * v;
    if (sh.lightShape) s.emission = {};
    return s;
}

/// One sample of a light as seen from a surface point.
template <class T>
struct LightSampleOf {
    Vec3T<T> L;                  //!< unit direction used for shading
    Vec3T<T> irradiance;         //!< unshadowed, at normal incidence; zero when the light misses P
    Vec3T<T> shadowDir;          //!< unit direction of the shadow ray (towards the sampled point)
    T shadowDistance = T(0.0f);  //!< where the shadow ray stops (infinite for directional lights)

    /// False when the light sends nothing to the point (behind a rect light, outside a spot's
    /// cone): no shadow ray is worth tracing.
    FP_HD MaskOf<T> reaches() const { return irradiance.x + irradiance.y + irradiance.z > 0.0f; }
};
/// A light's sample for one point (T: float lanes, for as many points).
using LightSample = LightSampleOf<float>;

/// A light as per-pixel code samples it, on either backend: a Light relative to a RayScene's
/// origin, with what its sampling needs worked out once on the host.
struct LightView {
    LightType type = LightType::Point;
    Vec3f radiance;        //!< colour × intensity
    Vec3d position;        //!< relative to the origin (point, spot, rect centre)
    Vec3f direction;       //!< unit, the way the light travels (directional, spot axis)
    Vec3f halfU, halfV;    //!< rect
    float extent = 0;      //!< sphere radius (point, spot) or the cone's half angle (directional)
    float tanExtent = 0;   //!< tan(extent) (directional)
    float cosOuter = 0, cosInner = 1;  //!< spot

    static LightView of(const Light& light, const Vec3d& origin);
    /// A rect light, a directional light with a source angle, a point or spot with a radius.
    FP_HD bool hasExtent() const { return type == LightType::Rect || extent > 0.0f; }
};

/// Samples `light` at (u, v) ∈ [0,1)² for the point P, whose rays leave from `origin` (its
/// SurfacePoint::rayOrigin, which a rect light's sample aims from); T: float, or float lanes (as
/// many points a vector, every lane the same operations in the same order).
template <class T>
FP_HD FP_HOT_INLINE LightSampleOf<T> sampleLightOf(const LightView& light, const Vec3T<T>& P,
                                                   const Vec3T<T>& origin, T u, T v) {
    using D = DoubleOf<T>;
    using V3 = Vec3T<T>;
    LightSampleOf<T> out;
    if (light.type == LightType::Rect) {
        const Vec3f hu = light.halfU, hv = light.halfV;
        const Vec3f nl = normalize(cross(hu, hv));
        const float area = 4.0f * length(cross(hu, hv));
        const V3 q = V3(Vec3f(light.position)) + V3(hu) * (2.0f * u - 1.0f) + V3(hv) * (2.0f * v - 1.0f);
        const V3 d = q - origin;
        const T dist = length(d);
        out.L = out.shadowDir = d / dist;
        // Stop just short of the emitter so its own quad does not shadow it.
        out.shadowDistance = dist * (1.0f - 1e-4f);
        const T cosL = -dot(out.L, V3(nl));
        out.irradiance = ifThenElse(cosL > 0.0f, V3(light.radiance) * (cosL * area / (dist * dist)), V3{});
        return out;
    }
    T maxDist;
    T irradiance;
    if (light.type == LightType::Directional) {
        out.L = V3(-light.direction);
        irradiance = T(1.0f);
        maxDist = T(std::numeric_limits<float>::infinity());
    } else {
        const Vec3T<D> toLight = Vec3T<D>(light.position) - Vec3T<D>{toDouble(P.x), toDouble(P.y), toDouble(P.z)};
        const D dist = length(toLight);
        out.L = {toFloat(toLight.x / dist), toFloat(toLight.y / dist), toFloat(toLight.z / dist)};
        irradiance = toFloat(D(1.0) / (dist * dist));
        maxDist = toFloat(dist);
        if (light.type == LightType::Spot)
            irradiance = irradiance * Light::spotMaskOf(dot(-out.L, V3(light.direction)),
                                                        light.cosOuter, light.cosInner);
    }
    out.irradiance = V3(light.radiance) * irradiance;
    out.shadowDir = out.L;
    T tfar = maxDist;
    if (light.extent > 0.0f) {
        V3 t, b;
        orthonormalBasis(out.L, t, b);
        T sinPhi, cosPhi;
        sinCos<T>(2.0f * kPiF * v, sinPhi, cosPhi);
        const T r = sqrtOf(u);
        const V3 disk = t * cosPhi + b * sinPhi;
        if (light.type == LightType::Directional) {
            // A disk of the cone's tangent at unit distance approximates the cone.
            out.shadowDir = normalize(out.L + disk * (r * light.tanExtent));
        } else {
            const V3 q = out.L * maxDist + disk * (r * light.extent);
            tfar = length(q);
            out.shadowDir = q / tfar;
        }
    }
    out.shadowDistance = tfar * (1.0f - 1e-5f);
    return out;
}

/// Samples `light` at (u, v) ∈ [0,1)² for the point `s` (DirectLighting::sample).
FP_HD inline LightSample sampleLight(const LightView& light, const SurfacePoint& s, float u,
                                     float v) {
    return sampleLightOf<float>(light, s.position,
                                light.type == LightType::Rect ? s.rayOrigin() : s.position, u, v);
}

/// Jittered stratified 2D sample k of n (n rounded to a square grid; else two plain draws),
/// drawn from `rng` (a stream's state, advanced); T: float, or float lanes (one stream a lane).
template <class T>
FP_HD inline void stratifiedSampleOf(int k, int n, UIntOf<T>& rng, T& u, T& v) {
    const int rounded = int(std::sqrt(float(n)) + 0.5f);  // lround: n > 0
    const int side = rounded > 1 ? rounded : 1;
    if (side * side != n) {
        u = nextFloatOf<T>(rng);
        v = nextFloatOf<T>(rng);
        return;
    }
    u = (float(k % side) + nextFloatOf<T>(rng)) / float(side);
    v = (float(k / side) + nextFloatOf<T>(rng)) / float(side);
}
FP_HD inline void stratifiedSample(int k, int n, Rng& rng, float& u, float& v) {
    uint32_t state = rng.state();
    stratifiedSampleOf<float>(k, n, state, u, v);
    rng = Rng::resume(state);
}

/// Whether a light is sampled at all (n > 1 samples, or a rect light) or once at its centre
/// (u = v = 0.5).
FP_HD inline bool sampledAcross(const LightView& light, int n) {
    return n > 1 || light.type == LightType::Rect;
}

/// The samples of `light` a shading point takes: `samples` of a light with extent, one of a
/// punctual light.
FP_HD inline int samplesOf(const LightView& light, int samples) {
    return light.hasExtent() ? samples : 1;
}

/// What light sample `ls` (its cosine NoL > 0) adds to the reflected radiance of a point of
/// normal N, view vector V and BRDF (diffuse, specular, roughness) when unblocked: the BRDF ×
/// irradiance × cosine; T: float or float lanes.
template <class T>
FP_HD Vec3T<T> lightValueOf(const Vec3T<T>& diffuse, const Vec3T<T>& specular, T roughness,
                            const Vec3T<T>& N, const Vec3T<T>& V, const LightSampleOf<T>& ls,
                            T NoL) {
    return brdfOf<T>(diffuse, specular, roughness, N, V, ls.L) * ls.irradiance * NoL;
}

/// The light samples shadeLights takes at `s`, in its order: for each light of `lights` in turn,
/// `samples` stratified samples of a light with extent (one of a punctual light), then
/// `onLightDone(n)` with the light's sample count; `onSample(ls, NoL)` for each sample whose
/// light reaches `s` from above (NoL > 0; what it adds when unblocked is lightValue's). A wave
/// of reflection hits draws the same samples in SIMD lanes (shading/ReflectionHitLanes.h: these
/// functions over float lanes, every hit a lane).
template <class Lights, class OnSample, class OnLightDone>
FP_HD void drawLightRays(const Lights& lights, int samples, const SurfacePoint& s, Rng& rng,
                         OnSample&& onSample, OnLightDone&& onLightDone) {
    for (int i = 0; i < lights.lightCount(); ++i) {
        const LightView& light = lights.lightView(i);
        const int n = samplesOf(light, samples);
        for (int k = 0; k < n; ++k) {
            float u = 0.5f, v = 0.5f;
            if (sampledAcross(light, n)) stratifiedSample(k, n, rng, u, v);
            const LightSample ls = sampleLight(light, s, u, v);
            const float NoL = dot(s.normal, ls.L);
            if (NoL <= 0.0f || !ls.reaches()) continue;
            onSample(ls, NoL);
        }
        onLightDone(n);
    }
}

/// lightValueOf at shading point `s`.
FP_HD inline Vec3f lightValue(const SurfacePoint& s, const LightSample& ls, float NoL) {
    return lightValueOf<float>(s.brdf.diffuseColor, s.brdf.specularColor, s.brdf.roughness,
                               s.normal, s.toViewer, ls, NoL);
}

/// Reflected radiance towards V from every light of `lights` (DirectLighting, or a tracer of
/// Bvh.h's on either backend: lightCount(), lightView(i), visible(s, sample)): drawLightRays'
/// samples, each light's unblocked ones averaged over its sample count; `shadowed` false traces
/// no shadow rays (every light unshadowed).
template <class Lights, class Count>
FP_HD Vec3f shadeLights(const Lights& lights, int samples, const SurfacePoint& s, Rng& rng,
                        Count& shadowRays, bool shadowed) {
    Vec3f total, sum;
    drawLightRays(
        lights, samples, s, rng,
        [&](const LightSample& ls, float NoL) {
            if (shadowed) {
                ++shadowRays;
                if (!lights.visible(s, ls)) return;
            }
            sum += lightValue(s, ls, NoL);
        },
        [&](int n) {
            total += sum * (1.0f / float(n));
            sum = {};
        });
    return total;
}

class DirectLighting {
public:
    /// `samples`: shadow (and area) samples for lights with extent; punctual lights use one.
    DirectLighting(const RayScene& scene, int samples);

    /// Reflected radiance towards V from all lights; `shadowed` false traces no shadow rays (every
    /// light unshadowed).
    Vec3f shade(const SurfacePoint& s, Rng& rng, uint64_t& shadowRays, bool shadowed = true) const;

    /// Samples `light` at (u, v) ∈ [0,1)² for the point `s`.
    LightSample sample(const Light& light, const SurfacePoint& s, float u, float v) const;
    /// True when nothing blocks the sample's shadow ray from `s`.
    bool visible(const SurfacePoint& s, const LightSample& ls) const;
    /// A rect light, a directional light with a source angle, a point or spot with a radius.
    static bool hasExtent(const Light& light);
    /// The scene's lights as sampleLight reads them, in the scene's order.
    const std::vector<LightView>& lightViews() const { return mLights; }
    int lightCount() const { return int(mLights.size()); }
    const LightView& lightView(int i) const { return mLights[std::size_t(i)]; }
    /// Light samples per light with extent (the constructor's `samples`).
    int samples() const { return mSamples; }

private:
    const RayScene& mScene;
    int mSamples;
    std::vector<LightView> mLights;
};

}  // namespace fp
