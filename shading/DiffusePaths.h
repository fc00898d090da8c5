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
        PathHit h;
        fillPathHit(c.scene->intersect(org, dir, tMin, tMax), org, dir, h);
        return h;
    }
    /// `out`, the path's hit from Embree's hit of the ray org + t·dir (or its miss), filled in
    /// place.
    void fillPathHit(const RayHit& hit, const Vec3f& org, const Vec3f& dir, PathHit& out) const {
        out.hit = hit.hit;
        if (!hit.hit) {
            out.t = -1.0f;
            return;
        }
        out.t = hit.t;
        out.surface = surfaceAt(*c.scene, hit, org, dir);
        out.surface.emission = c.scene->scene().emissionTowardsSurfaces(hit.mesh);
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

/// A path in flight: the ray it traces next and what it has gathered so far. traceDiffusePath
/// runs one to its end; a wave (DiffusePathWave.h) holds many and traces each step's rays
/// together, through the same steps below, so each path ends with the same bits either way.
struct PathState {
    Vec3f org, dir;
    float tMin = 0.0f;
    Vec3f throughput{1, 1, 1};
    int bounce = 0;
    bool done = false;
    DiffusePath out;
};

/// A path whose first ray is org + t·dir, t from tMin (none at all with no bounces).
FP_HD inline PathState startPath(const DiffusePathSettings& c, Vec3f org, Vec3f dir, float tMin) {
    PathState p;
    p.org = org;
    p.dir = dir;
    p.tMin = tMin;
    p.done = c.bounces <= 0;
    return p;
}

/// The path's ray found `hit` (or nothing): a miss ends it (a bounce ray's miss, or the first's
/// when asked, takes the sky), and so does a first hit beyond giDistance; otherwise the hit adds
/// its emission when asked. True when the path goes on to the lights at the hit.
template <class Tracer>
FP_HD bool reachHit(const Tracer& tracer, const DiffusePathSettings& c, PathState& p,
                    const PathHit& hit) {
    if (!hit.hit) {
        // The first ray's sky is the sky light's own diffuse term, another pass's.
        if (tracer.hasSky() && (p.bounce > 0 || c.skyOnFirstRay))
            p.out.radiance += p.throughput * tracer.sky(p.dir);
        p.done = true;
        return false;
    }
    if (p.bounce == 0) {
        p.out.firstHit = hit.t;
        if (hit.t > c.giDistance) {
            p.done = true;
            return false;
        }
    }
    // No emission at hits unless asked: Unreal adds only the lights' light (and no lightmap).
    if (c.emissionAtHits) p.out.radiance += p.throughput * hit.surface.emission;
    return true;
}

/// Which of `lights` lights a sample whose first number is `pick` takes: int(pick · lights), the
/// last at most; T: float, or float lanes (each lane's index as a float).
template <class T>
FP_HD T lightIndexOf(T pick, int lights) {
    return minLike(floorOf(pick * float(lights)), T(float(lights - 1)));
}

/// One light sample at a point of unit normal `normal` and diffuse colour `diffuseColor`, drawing
/// its three numbers from `rng` (a stream's state, advanced): the light picked uniformly and
/// sampled there (`sampleAt(index, u, v)`, index lightIndexOf's), `keep` where that light reaches
/// the point from above (its shadow ray worth tracing) and `lit`, what the sample adds when its
/// shadow ray is unblocked. T: float, or float lanes (as many points a vector).
template <class T, class SampleAt>
FP_HD FP_HOT_INLINE void drawLightSample(int lights, UIntOf<T>& rng, const Vec3T<T>& normal,
                                         const Vec3T<T>& diffuseColor, SampleAt&& sampleAt,
                                         LightSampleOf<T>& ls, MaskOf<T>& keep, Vec3T<T>& lit) {
    const T pick = nextFloatOf<T>(rng);
    const T u = nextFloatOf<T>(rng);
    const T v = nextFloatOf<T>(rng);
    ls = sampleAt(lightIndexOf(pick, lights), u, v);
    const T cosine = dot(normal, ls.L);
    keep = ls.reaches() & !(cosine <= 0.0f);
    lit = diffuseColor * ls.irradiance * (cosine / kPiF);
}

/// The light samples at hit `s`: each of `nee` picks one light uniformly (drawLightSample);
/// `onShadowRay(ls, lit)` is called, in order, for each sample whose light reaches `s` from above,
/// with what it adds when its shadow ray is unblocked (`lit`). Draws nothing without lights or
/// samples.
template <class Lights, class OnShadowRay>
FP_HD void drawLightSamples(const Lights& lights, const DiffusePathSettings& c,
                            const SurfacePoint& s, Rng& rng, OnShadowRay&& onShadowRay) {
    const int n = lights.lightCount();
    if (n == 0 || c.nee <= 0) return;
    uint32_t state = rng.state();
    auto sampleAt = [&](float index, float u, float v) {
        return sampleLight(lights.lightView(int(index)), s, u, v);
    };
    for (int k = 0; k < c.nee; ++k) {
        LightSample ls;
        bool keep;
        Vec3f lit;
        drawLightSample<float>(n, state, s.normal, s.brdf.diffuseColor, sampleAt, ls, keep, lit);
        if (keep) onShadowRay(ls, lit);
    }
    rng = Rng::resume(state);
}

/// The light estimate from the unblocked samples' sum (in the order drawn): × the light count
/// over the sample count, the pick's pdf.
FP_HD inline Vec3f lightEstimate(const Vec3f& unblocked, int lights, int nee) {
    if (lights == 0 || nee <= 0) return unblocked;
    return unblocked * (float(lights) / float(nee));
}

/// The diffuse light the lights send to hit `s`, each sample's shadow ray traced at once.
template <class Tracer, class Count>
FP_HD Vec3f sampleLights(const Tracer& tracer, const DiffusePathSettings& c, const SurfacePoint& s,
                         Rng& rng, Count& shadowRays) {
    Vec3f sum;
    drawLightSamples(tracer, c, s, rng, [&](const LightSample& ls, const Vec3f& lit) {
        ++shadowRays;
        if (tracer.visible(s, ls)) sum += lit;
    });
    return lightEstimate(sum, tracer.lightCount(), c.nee);
}

/// After the lights at hit `s` (`lights`, lightEstimate's): the path adds them, then ends at its
/// last bounce or draws its next cosine bounce, the hit's diffuse colour its throughput
/// (BxDF·cos/pdf = DiffuseColor).
FP_HD inline void leaveHit(const DiffusePathSettings& c, PathState& p, const SurfacePoint& s,
                           const Vec3f& lights, Rng& rng) {
    p.out.radiance += p.throughput * lights;
    if (p.bounce + 1 >= c.bounces) {
        p.done = true;
        return;
    }
    const float u = rng.nextFloat(), v = rng.nextFloat();
    p.dir = cosineHemisphere(s.normal, u, v);
    p.org = s.rayOrigin();
    p.tMin = 0.0f;  // every ray of the path keeps c.reach, as Unreal reuses its ray description
    p.throughput = p.throughput * s.brdf.diffuseColor;
    ++p.bounce;
}

/// One step of path `p` (not done): its next ray, and at a hit the lights there and the ray after;
/// `rays` and `shadowRays` count what it traced.
template <class Tracer, class Count>
FP_HD void tracePathStep(const Tracer& tracer, const DiffusePathSettings& c, PathState& p,
                         Rng& rng, Count& rays, Count& shadowRays) {
    ++rays;
    const PathHit hit = tracer.closestHit(p.org, p.dir, p.tMin, c.reach);
    if (reachHit(tracer, c, p, hit))
        leaveHit(c, p, hit.surface, sampleLights(tracer, c, hit.surface, rng, shadowRays), rng);
}

/// Path `p` to its end, one ray at a time; `rays` and `shadowRays` count what it traced.
template <class Tracer, class Count>
FP_HD DiffusePath traceDiffusePath(const Tracer& tracer, const DiffusePathSettings& c, PathState p,
                                   Rng& rng, Count& rays, Count& shadowRays) {
    while (!p.done) tracePathStep(tracer, c, p, rng, rays, shadowRays);
    return p.out;
}

/// The path along org + t·dir, t from tMin; `rays` and `shadowRays` count what it traced.
template <class Tracer, class Count>
FP_HD DiffusePath traceDiffusePath(const Tracer& tracer, const DiffusePathSettings& c, Vec3f org,
                                   Vec3f dir, float tMin, Rng& rng, Count& rays, Count& shadowRays) {
    return traceDiffusePath(tracer, c, startPath(c, org, dir, tMin), rng, rays, shadowRays);
}

#if !defined(__CUDACC__)
/// traceDiffusePath through Embree's scene, as `c` describes it.
inline DiffusePath traceDiffusePath(const DiffusePathSetup& c, Vec3f org, Vec3f dir, float tMin,
                                    Rng& rng, uint64_t& rays, uint64_t& shadowRays) {
    return traceDiffusePath(EmbreeTracer{c}, c, org, dir, tMin, rng, rays, shadowRays);
}
#endif

}  // namespace fp
