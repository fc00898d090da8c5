#pragma once
// hybrid_reflections' fallback, written once for every tracer and backend: the ray SSR's march
// could not finish, traced from the pixel's surface through the scene and lit as rt_reflections
// lights its hits (algorithms §12.3). SSR's kernel (ssr::run) calls it; execute() runs it with
// CpuPixels through Embree (EmbreeTracer) or, with traversal "bvh", through framepass's BVH
// (BvhTracer) — the code the GPU runs (HybridReflectionsPass.cu).
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/Random.h"
#include "passes/rt_reflections/RTReflectionsKernel.h"
#include "passes/ssr/SSRKernel.h"
#include "passes/ssr/SSRPass.h"
#include "shading/RayOriginBias.h"
#include "shading/ReflectionHits.h"

#include <bit>
#include <cstdint>
#include <limits>

namespace fp::hybrid_reflections {

// A fallback ray that saw the sky: its distance, as rt_reflections writes it (Unreal's).
constexpr double kSkyDistance = 1e20;

enum FallbackCounter {
    kFallbackRays, kFallbackHits, kSkyRays, kShadowRays, kIndirectRays, kFallbackCounters
};

/// SSR's fallback (ssr::ssrPixel) through `Tracer`.
template <class Tracer>
struct SceneFallback {
    Tracer tracer;
    rtr::Sky sky;
    bool shadowed;        // one shadow ray a light at a hit
    int lightSamples;     // samples of a light with extent
    int indirectBounces;  // a hit's traced indirect light (0: the sky's SH)
    Vec3d eyeOffset;      // the camera relative to the scene's origin
    RayBias bias;
    uint32_t rngKey;
    unsigned long long* counts;  // FallbackCounter, where the pixels run

    FP_HD ssr::RaySample operator()(int x, int y, const Vec3d& offset, const Vec3f& N,
                                    const Vec3f& L, float roughness) const {
        addSharedCount(counts + kFallbackRays, 1);
        const Vec3f org = biasedRayOrigin(pixelSurfaceAt(eyeOffset, offset), N, dot(N, L), bias);
        const Vec3f eyeToOrigin = org - Vec3f(eyeOffset);
        ssr::RaySample s;
        const PathHit hit =
            tracer.closestHit(org, L, 0.0f, std::numeric_limits<float>::infinity());
        if (!hit.hit) {
            if (!sky.on)
                return s;  // nothing: the sample's share of the coverage is the captures'
            addSharedCount(counts + kSkyRays, 1);
            const Vec3f c = sky.cube.sample(L, sky.cube.mipForRoughness(roughness));
            s = {true, {c.x, c.y, c.z}, 1.0f, Vec3d(eyeToOrigin) + Vec3d(L) * kSkyDistance};
            return s;
        }
        addSharedCount(counts + kFallbackHits, 1);
        // Each ray its own light samples: the key takes the direction's bits.
        Rng rng = Rng::fromKey(
            rngKey ^ std::bit_cast<uint32_t>(L.x) ^ (std::bit_cast<uint32_t>(L.y) << 1), x, y);
        uint32_t shadowRays = 0, indirectRays = 0;
        const Vec3f c = lightReflectionHit(tracer, hit.surface, sky.on ? &sky.sh : nullptr,
                                           shadowed, lightSamples, indirectBounces, rng,
                                           shadowRays, indirectRays);
        if (shadowRays) addSharedCount(counts + kShadowRays, shadowRays);
        if (indirectRays) addSharedCount(counts + kIndirectRays, indirectRays);
        s = {true, {c.x, c.y, c.z}, 1.0f, Vec3d(eyeToOrigin + L * hit.t)};
        return s;
    }
};

/// SSR's kernel with `fallback`, on either backend: every ray SSR's, as `ssr` runs it.
template <class Ports, class Pixels, class Fallback>
void runSsr(PassContext& ctx, const Ports& ports, const Pixels& pixels, const SSRParams& p,
            const Fallback& fallback) {
    ssr::run(ctx, ports, pixels, ssr::effectiveQuality(p.quality, p.postProcessQuality, p.intensity),
             p.maxRoughness, p.intensity, p.temporal, fallback);
}

}  // namespace fp::hybrid_reflections
