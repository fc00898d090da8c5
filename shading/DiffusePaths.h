#pragma once
// Unreal 4.27's brute-force ray-traced GI path (algorithms §12.2), from a ray already leaving a
// surface: at each hit next event estimation (one light picked uniformly per sample, its shadow
// ray traced), no emission at hits, the sky only for a bounce ray's miss when asked, then a
// cosine bounce with the hit's diffuse colour as throughput. rt_global_illumination starts its
// paths from the GBuffer; the hybrid continues a screen-space ray that found nothing with one;
// a reflection hit's traced indirect light is one (with the sky and emission Unreal's RTGI leaves
// out, shading/ReflectionHits.h).
//
// The path is written once, as an FP_HD template over what its rays meet (a tracer): Embree's
// scene on the CPU (EmbreeTracer), or framepass's BVH (BvhTracer) on the CPU and on the GPU,
// the same code either way.
#include "foundation/Bvh.h"
#include "foundation/Environment.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/ShadingModel.h"
#include "foundation/Random.h"
#include "foundation/RayScene.h"
#include "foundation/Sampling.h"
#include "shading/DirectLighting.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace fp {

/// How a path runs, whatever traces it.
struct DiffusePathSettings {
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

struct DiffusePathSetup : DiffusePathSettings {
    const RayScene* scene = nullptr;
    const DirectLighting* lighting = nullptr;  //!< the scene's lights, sampled
    const SkyLight* sky = nullptr;  //!< null: a bounce ray's miss adds nothing
};

/// What one path brought back: the radiance along the first ray (irradiance/π units once averaged
/// over cosine-distributed first rays) and where the first ray hit (t < 0: it missed).
struct DiffusePath {
    Vec3f radiance;
    float firstHit = -1.0f;
};

/// A path's hit: where, its shading point and (when the path adds it) its emission.
struct PathHit {
    bool hit = false;
    float t = -1.0f;
    SurfacePoint surface;
};

#if !defined(__CUDACC__)
// (Host code only: nvcc refuses an FP_HD template instantiated with host-only calls, even for
// the host.)
/// The CPU's scene through Embree: RayScene's queries, DirectLighting's light samples, the sky.
struct EmbreeTracer {
    const DiffusePathSetup& c;

    PathHit closestHit(const Vec3f& org, const Vec3f& dir, float tMin, float tMax) const {
        const RayHit hit = c.scene->intersect(org, dir, tMin, tMax);
        if (!hit.hit) return {};
        PathHit h{true, hit.t, surfaceAt(*c.scene, hit, org, dir)};
        h.surface.emission = c.scene->scene().emissionTowardsSurfaces(hit.mesh);
        return h;
    }
    int lightCount() const { return c.lighting->lightCount(); }
    const LightView& lightView(int i) const { return c.lighting->lightView(i); }
    bool visible(const SurfacePoint& s, const LightSample& ls) const {
        return c.lighting->visible(s, ls);
    }
    bool hasSky() const { return c.sky != nullptr; }
    Vec3f sky(const Vec3f& dir) const { return c.sky->radiance(dir); }
};
#endif

/// framepass's BVH on either backend: closest hits and shadow rays through traceBvhHit, the
/// lights as LightViews; no sky (a pass whose paths read the sky keeps to the CPU).
struct BvhTracer {
    BvhView bvh;
    const LightView* lights = nullptr;
    int numLights = 0;

    FP_HD PathHit closestHit(const Vec3f& org, const Vec3f& dir, float tMin, float tMax) const {
        const BvhHit hit = traceBvhHit(bvh, org, dir, tMin, tMax, BvhQuery{});
        if (!hit.hit()) return {};
        return {true, hit.t, surfaceAt(bvh, hit, org, dir)};
    }
    FP_HD int lightCount() const { return numLights; }
    FP_HD const LightView& lightView(int i) const { return lights[i]; }
    FP_HD bool visible(const SurfacePoint& s, const LightSample& ls) const {
        return traceBvh(bvh, s.rayOrigin(), ls.shadowDir, 0.0f, ls.shadowDistance,
                        BvhQuery{true, false, 0}) < 0.0f;
    }
    FP_HD bool hasSky() const { return false; }
    FP_HD Vec3f sky(const Vec3f&) const { return {}; }
};

/// A BvhTracer over `ports`' BVH (HostPorts or DevicePorts) and `lighting`'s lights: read in place
/// on the host, copied to the device for a GPU pass, where `keep` holds the copy while the pass's
/// kernels run. Every pass that traces framepass's BVH makes its tracer here.
template <class Ports>
BvhTracer bvhTracerFor(const Ports& ports, const DirectLighting& lighting,
                       std::shared_ptr<const LightView>& keep) {
    const std::vector<LightView>& views = lighting.lightViews();
    keep = ports.constants(views.data(), views.size());
    return {ports.bvh(), keep.get(), int(views.size())};
}

/// The colour a GBuffer pixel's diffuse light is multiplied by: BaseColor·(1 − Metallic), or the
/// stored base colour itself for a subsurface-profile pixel (algorithms §12.2).
FP_HD inline Vec3f gbufferDiffuseColor(const Vec3f& baseColor, float metallic, float shadingModel) {
    const bool profile = truncToInt(shadingModel, 0, 255) == kSubsurfaceProfile;
    return profile ? baseColor : baseColor * (1.0f - metallic);
}

/// The diffuse light the lights send to hit `s`: each of `nee` samples picks one light uniformly
/// and traces its shadow ray; the sum is scaled by the light count over the sample count (the
/// pick's pdf).
template <class Tracer, class Count>
FP_HD Vec3f sampleLights(const Tracer& tracer, const DiffusePathSettings& c, const SurfacePoint& s,
                         Rng& rng, Count& shadowRays) {
    const int n = tracer.lightCount();
    Vec3f sum;
    if (n == 0 || c.nee <= 0) return sum;
    for (int k = 0; k < c.nee; ++k) {
        const float pick = rng.nextFloat(), u = rng.nextFloat(), v = rng.nextFloat();
        const int picked = int(pick * float(n));
        const LightSample ls =
            sampleLight(tracer.lightView(picked < n - 1 ? picked : n - 1), s, u, v);
        const float cosine = dot(s.normal, ls.L);
        if (!ls.reaches() || cosine <= 0.0f) continue;
        ++shadowRays;
        if (!tracer.visible(s, ls)) continue;
        sum += s.brdf.diffuseColor * ls.irradiance * (cosine / kPiF);
    }
    return sum * (float(n) / float(c.nee));
}

/// The path along org + t·dir, t from tMin; `rays` and `shadowRays` count what it traced.
template <class Tracer, class Count>
FP_HD DiffusePath traceDiffusePath(const Tracer& tracer, const DiffusePathSettings& c, Vec3f org,
                                   Vec3f dir, float tMin, Rng& rng, Count& rays, Count& shadowRays) {
    DiffusePath out;
    Vec3f throughput{1, 1, 1};
    const float reach = c.reach;  // every ray of the path, as Unreal reuses its ray description
    for (int bounce = 0; bounce < c.bounces; ++bounce) {
        ++rays;
        const PathHit hit = tracer.closestHit(org, dir, tMin, reach);
        if (!hit.hit) {
            // The first ray's sky is the sky light's own diffuse term, another pass's.
            if (tracer.hasSky() && (bounce > 0 || c.skyOnFirstRay))
                out.radiance += throughput * tracer.sky(dir);
            return out;
        }
        if (bounce == 0) {
            out.firstHit = hit.t;
            if (hit.t > c.giDistance) return out;
        }
        const SurfacePoint& s = hit.surface;
        // No emission at hits unless asked: Unreal adds only the lights' light (and no lightmap).
        if (c.emissionAtHits) out.radiance += throughput * s.emission;
        out.radiance += throughput * sampleLights(tracer, c, s, rng, shadowRays);
        if (bounce + 1 == c.bounces) return out;
        // The next diffuse bounce: BxDF·cos/pdf = DiffuseColor.
        const float u = rng.nextFloat(), v = rng.nextFloat();
        dir = cosineHemisphere(s.normal, u, v);
        org = s.rayOrigin();
        tMin = 0.0f;
        throughput = throughput * s.brdf.diffuseColor;
    }
    return out;
}

#if !defined(__CUDACC__)
/// traceDiffusePath through Embree's scene, as `c` describes it.
inline DiffusePath traceDiffusePath(const DiffusePathSetup& c, Vec3f org, Vec3f dir, float tMin,
                                    Rng& rng, uint64_t& rays, uint64_t& shadowRays) {
    return traceDiffusePath(EmbreeTracer{c}, c, org, dir, tMin, rng, rays, shadowRays);
}
#endif

}  // namespace fp
