#pragma once
// Unreal 4.27's brute-force ray-traced GI path (algorithms §12.2), from a ray already leaving a
// surface: at each hit next event estimation (one light picked uniformly per sample, its shadow
// ray traced), no emission at hits, the sky only for a bounce ray's miss when asked, then a
// cosine bounce with the hit's diffuse colour as throughput. rt_global_illumination starts its
// paths from the GBuffer; the hybrid continues a screen-space ray that found nothing with one;
// a reflection hit's traced indirect light is one (with the sky and emission Unreal's RTGI leaves
// out, shading/ReflectionHits.h).
#include "foundation/Environment.h"
#include "foundation/FloatToInt.h"
#include "foundation/ShadingModel.h"
#include "foundation/Random.h"
#include "foundation/RayScene.h"
#include "shading/DirectLighting.h"

#include <cstdint>
#include <vector>

namespace fp {

struct DiffusePathSetup {
    const RayScene* scene = nullptr;
    const DirectLighting* lighting = nullptr;
    const std::vector<Light>* lights = nullptr;
    const SkyLight* sky = nullptr;  //!< null: a bounce ray's miss adds nothing
    /// The first ray's miss takes the sky too (a reflection hit's indirect light); Unreal's RTGI
    /// leaves it to the sky light's own diffuse term.
    bool skyOnFirstRay = false;
    /// Hits add their emission (a light's visible shape excepted); Unreal's RTGI adds none.
    bool emissionAtHits = false;
    int bounces = 1;                //!< hits shaded per path (MaxBounces)
    int nee = 2;                    //!< light samples at each hit
    float reach = 1e30f;            //!< the first ray's length
    float giDistance = 1e30f;       //!< a first hit beyond this ends the path unshaded
};

/// What one path brought back: the radiance along the first ray (irradiance/π units once averaged
/// over cosine-distributed first rays) and where the first ray hit (t < 0: it missed).
struct DiffusePath {
    Vec3f radiance;
    float firstHit = -1.0f;
};

/// The colour a GBuffer pixel's diffuse light is multiplied by: BaseColor·(1 − Metallic), or the
/// stored base colour itself for a subsurface-profile pixel (algorithms §12.2).
inline Vec3f gbufferDiffuseColor(const Vec3f& baseColor, float metallic, float shadingModel) {
    const bool profile = truncToInt(shadingModel, 0, 255) == kSubsurfaceProfile;
    return profile ? baseColor : baseColor * (1.0f - metallic);
}

/// The path along org + t·dir, t from tMin; `rays` and `shadowRays` count what it traced.
DiffusePath traceDiffusePath(const DiffusePathSetup& c, Vec3f org, Vec3f dir, float tMin, Rng& rng,
                             uint64_t& rays, uint64_t& shadowRays);

}  // namespace fp
