#pragma once
// What a reflection ray traced through the scene brings back (algorithms §12.4), shared by
// rt_reflections and the reflection hybrid: at its closest hit, the hit lit as Unreal's material
// hit shader lights it; on a miss, the sky light's prefiltered cubemap.
#include "foundation/Environment.h"
#include "foundation/Random.h"
#include "foundation/RayScene.h"
#include "foundation/HostDevice.h"
#include "foundation/Sampling.h"
#include "shading/Cubemap.h"
#include "shading/DiffusePaths.h"
#include "shading/DirectLighting.h"
#include "shading/SphericalHarmonics.h"

#include <cstdint>
#include <memory>

namespace fp {

/// The sky light as reflection rays see it: its cubemap (a miss) and its SH (a hit's diffuse).
struct ReflectedSky {
    const SkyLight* source = nullptr;
    Cubemap cube;
    SH3 sh;

    /// `cached` when it was made from `sky`, else a new one (rendered at Cubemap::kSkyLightSize
    /// and projected); null when the sky light is off.
    static std::shared_ptr<const ReflectedSky> of(const SkyLight& sky,
                                                  std::shared_ptr<const ReflectedSky> cached);
    /// What a ray along L that hits nothing sees, for a surface of `roughness`.
    Vec3f miss(const Vec3f& L, float roughness) const {
        return cube.sample(L, cube.mipForRoughness(roughness));
    }
};

/// How reflection hits are lit, shared by rt_reflections and hybrid_reflections' fallback.
struct ReflectionHitLighting {
    const RayScene* scene = nullptr;
    const DirectLighting* lighting = nullptr;
    const ReflectedSky* sky = nullptr;  //!< null: the sky light is off
    bool shadowed = true;               //!< one shadow ray a light; false: every light unshadowed
    /// The hit's diffuse indirect light. 0, Unreal's: the sky light's SH irradiance, unshadowed
    /// (the precomputed indirect light; framepass has no lightmaps). n > 0, framepass's: traced,
    /// one cosine path of n bounces from the hit that sees the sky only through the scene's
    /// openings and other surfaces lit by the lights and their emission.
    int indirectBounces = 0;
};

/// What lighting reflection hits traced, for the run report.
struct ReflectionHitWork {
    uint64_t shadowRays = 0;    //!< at the hits (and along the indirect paths)
    uint64_t indirectRays = 0;  //!< the indirect paths' rays
};

/// A reflection hit's diffuse colour × its indirect light, drawn after its light samples:
/// `indirectBounces` > 0 one traced cosine path (with the sky and emission Unreal's RTGI leaves
/// out), else the sky's SH irradiance (`skySh`, null: no sky).
template <class Tracer, class Count>
FP_HD Vec3f reflectionHitIndirect(const Tracer& tracer, const SurfacePoint& s, const SH3* skySh,
                                  int indirectBounces, Rng& rng, Count& shadowRays,
                                  Count& indirectRays) {
    if (indirectBounces > 0) {
        // One cosine path: its radiance is the hit's irradiance/π, as the SH's diffuse term is.
        DiffusePathSettings path;
        path.skyOnFirstRay = true;
        path.emissionAtHits = true;
        path.bounces = indirectBounces;
        path.nee = 1;
        const float u = rng.nextFloat(), v = rng.nextFloat();
        const Vec3f dir = cosineHemisphere(s.normal, u, v);
        return s.brdf.diffuseColor *
               traceDiffusePath(tracer, path, s.rayOrigin(), dir, 0.0f, rng, indirectRays,
                                shadowRays)
                   .radiance;
    }
    if (skySh) return s.brdf.diffuseColor * skySh->diffuse(s.normal);
    return {};
}

/// What a reflection hit sends back from its emission, its lights' light and its indirect light
/// (reflectionHitIndirect's), clamped to ≥ 0.
FP_HD inline Vec3f reflectionHitRadiance(const Vec3f& emission, const Vec3f& lights,
                                         const Vec3f& indirect) {
    const Vec3f radiance = emission + lights + indirect;
    return {radiance.x < 0.0f ? 0.0f : radiance.x, radiance.y < 0.0f ? 0.0f : radiance.y,
            radiance.z < 0.0f ? 0.0f : radiance.z};  // std::max(·, 0), a NaN kept
}

/// The radiance a reflection hit `s` sends back along its ray, on either backend through a tracer
/// of DiffusePaths.h: every light of the tracer (`lightSamples` samples of a light with extent;
/// one shadow ray each when `shadowed`), the hit's emission, and its diffuse colour × its
/// indirect light (reflectionHitIndirect), clamped to ≥ 0.
template <class Tracer, class Count>
FP_HD Vec3f lightReflectionHit(const Tracer& tracer, const SurfacePoint& s, const SH3* skySh,
                               bool shadowed, int lightSamples, int indirectBounces, Rng& rng,
                               Count& shadowRays, Count& indirectRays) {
    // The hit as Unreal's material hit shader lights it: the lights (the view vector the ray's),
    // its emission, and its diffuse colour × its indirect light. A light's visible shape sends
    // no emission here: its reflection is the light's own specular, which deferred_lighting adds
    // (algorithms §12.4).
    const Vec3f lights = shadeLights(tracer, lightSamples, s, rng, shadowRays, shadowed);
    return reflectionHitRadiance(
        s.emission, lights,
        reflectionHitIndirect(tracer, s, skySh, indirectBounces, rng, shadowRays, indirectRays));
}

/// The radiance a reflection ray along L from `org` brings from its closest hit `hit`: every light
/// (with one shadow ray each when `shadowed`), the hit's emission (a light's visible shape sends
/// none: its reflection is the light's own specular), and its diffuse colour × its indirect light
/// (above); clamped to ≥ 0. `viewer` (non-null) replaces the ray's view vector (Unreal's hybrid
/// shades from the camera).
Vec3f shadeReflectionHit(const ReflectionHitLighting& how, const RayHit& hit, const Vec3f& org,
                         const Vec3f& L, Rng& rng, ReflectionHitWork& work,
                         const Vec3f* viewer = nullptr);

}  // namespace fp
