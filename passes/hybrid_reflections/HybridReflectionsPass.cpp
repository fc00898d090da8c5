#include "passes/hybrid_reflections/HybridReflectionsPass.h"

#include "framework/PassPorts.h"
#include "passes/ssr/SSRKernel.h"
#include "shading/DirectLighting.h"
#include "shading/RayOriginBias.h"

#include <atomic>
#include <bit>
#include <limits>

namespace fp {

namespace {

constexpr uint32_t kSeed = 0x48524546u;  // "HREF"
// A fallback ray that saw the sky: its distance, as rt_reflections writes it (Unreal's).
constexpr double kSkyDistance = 1e20;

enum FallbackCounter {
    kFallbackRays, kFallbackHits, kSkyRays, kShadowRays, kIndirectRays, kFallbackCounters
};

// SSR's fallback (ssr::ssrPixel): the ray the screen could not finish, traced from the pixel's
// surface through the scene and lit as rt_reflections lights its hits (algorithms §12.3).
struct SceneFallback {
    ReflectionHitLighting hits;
    Vec3d eyeOffset;  // the camera relative to the scene's origin
    RayBias bias;
    uint32_t rngKey;
    std::atomic<uint64_t>* counts;  // FallbackCounter

    ssr::RaySample operator()(int x, int y, const Vec3d& offset, const Vec3f& N, const Vec3f& L,
                              float roughness) const {
        counts[kFallbackRays].fetch_add(1, std::memory_order_relaxed);
        const Vec3f org = biasedRayOrigin(pixelSurfaceAt(eyeOffset, offset), N, dot(N, L), bias);
        const Vec3f eyeToOrigin = org - Vec3f(eyeOffset);
        ssr::RaySample s;
        const RayHit hit = hits.scene->intersect(org, L, 0.0f, std::numeric_limits<float>::infinity());
        if (!hit.hit) {
            if (!hits.sky)
                return s;  // nothing: the sample's share of the coverage is the captures'
            counts[kSkyRays].fetch_add(1, std::memory_order_relaxed);
            const Vec3f c = hits.sky->miss(L, roughness);
            s = {true, {c.x, c.y, c.z}, 1.0f, Vec3d(eyeToOrigin) + Vec3d(L) * kSkyDistance};
            return s;
        }
        counts[kFallbackHits].fetch_add(1, std::memory_order_relaxed);
        // Each ray its own light samples: the key takes the direction's bits.
        Rng rng = Rng::fromKey(rngKey ^ std::bit_cast<uint32_t>(L.x) ^ (std::bit_cast<uint32_t>(L.y) << 1), x, y);
        ReflectionHitWork work;
        const Vec3f c = shadeReflectionHit(hits, hit, org, L, rng, work);
        counts[kShadowRays].fetch_add(work.shadowRays, std::memory_order_relaxed);
        counts[kIndirectRays].fetch_add(work.indirectRays, std::memory_order_relaxed);
        s = {true, {c.x, c.y, c.z}, 1.0f, Vec3d(eyeToOrigin + L * hit.t)};
        return s;
    }
};

}  // namespace

ParamSpec<HybridReflectionsParams> HybridReflectionsPass::paramSpec() {
    ParamSpec<HybridReflectionsParams> s = SSRPass::paramSpecOf<HybridReflectionsParams>();
    s.add("normalBias", &Params::normalBias, "a fallback ray's origin bias, cm, as rt_reflections'")
        .range(0.01, 1e6)
        .cvar("r.RayTracing.Reflections.NormalBias");
    s.add("shadows", &Params::shadows,
          "0: a fallback hit's lights unshadowed; otherwise one shadow ray a light, as "
          "rt_reflections' hard shadows")
        .range(0, 2)
        .cvar("r.RayTracing.Reflections.Shadows");
    s.add("hitIndirectBounces", &Params::hitIndirectBounces,
          "a fallback hit's diffuse indirect light, as rt_reflections': 0 the sky light's SH, "
          "n > 0 traced by one cosine path of n bounces")
        .range(0, 16);
    return s;
}

PassIO HybridReflectionsPass::describe() const {
    // SSR's ports, all of them: its rays are SSR's.
    PassIO io = SSRPass(mParams).describe();
    io.roles.framepassOwn = true;
    io.roles.tracesRays = true;  // bench replays its fallback rays in bare Embree loops
    io.needsScene = true;
    return io;
}

PassMemory HybridReflectionsPass::memoryBytes(Extent frame) const {
    return SSRPass(mParams).memoryBytes(frame);  // SSR's rays and SSR's history
}

void HybridReflectionsPass::execute(PassContext& ctx) {
    const RayScene& rs = ctx.scene();
    mSky = ReflectedSky::of(rs.scene().environment.sky, mSky);
    const DirectLighting lighting(rs, 1);
    const CameraView& cam = ctx.frame().camera.current;
    std::atomic<uint64_t> counts[kFallbackCounters] = {};
    SceneFallback fallback{{&rs, &lighting, mSky.get(), mParams.shadows != 0, mParams.hitIndirectBounces},
                           cam.position - rs.origin(),
                           RayBias::fromCm(mParams.normalBias, float(rs.scene().centimetre())),
                           Rng::frameKey(ctx.frame().number, kSeed),
                           counts};
    ssr::run(ctx, HostPorts{ctx}, CpuPixels{},
             ssr::effectiveQuality(mParams.quality, mParams.postProcessQuality, mParams.intensity),
             mParams.maxRoughness, mParams.intensity, mParams.temporal, fallback);
    ctx.addWork("fallbackRays", counts[kFallbackRays]);
    ctx.addWork("fallbackHits", counts[kFallbackHits]);
    ctx.addWork("skyRays", counts[kSkyRays]);
    ctx.addWork("shadowRays", counts[kShadowRays]);
    if (mParams.hitIndirectBounces > 0) ctx.addWork("indirectRays", counts[kIndirectRays]);
}

}  // namespace fp
