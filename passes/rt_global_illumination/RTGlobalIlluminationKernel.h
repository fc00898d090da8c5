#pragma once
// rt_global_illumination's per-texel work (algorithms §12.2), written once for every tracer and
// backend: a texel's set-up from the GBuffer pixel it stands for, its cosine paths
// (traceDiffusePath), the resolve. execute() runs it with CpuPixels through Embree's scene
// (EmbreeTracer) or, with traversal "bvh", through framepass's BVH (BvhTracer) — the code the
// GPU runs with CudaPixels (RTGlobalIlluminationPass.cu).
#include "foundation/Camera.h"
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Random.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "foundation/UnrealRandom.h"
#include "framework/Pass.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Surface.h"
#include "shading/DiffusePaths.h"
#include "shading/RayOriginBias.h"

#include <cstdint>

namespace fp::rtgi {

inline constexpr const char* kDiffuse = "diffuse";
inline constexpr const char* kAo = "ao";
inline constexpr const char* kHitDistance = "hitDistance";

/// What every texel of a frame shares.
struct FrameSetup {
    CameraView camera;
    Vec3d eyeOffset;  // the eye relative to the RayScene origin
    Extent frame;     // the GBuffer's pixels
    int upscale;      // a texel stands for the top-left pixel of its upscale × upscale block
    int spp;
    float aoRadius, tMin;  // scene units
    float diffuseThreshold;
    RayBias bias;
    DiffusePathSettings paths;
    uint32_t rngKey;
};

/// The frame's planes, as the texels read and write them.
struct Frame {
    FrameSetup setup;
    PlaneView depth, model, normal[3], baseColor[3], metallic;
    PlaneSpan diffuse[3], ao, hitDistance;
};

enum Counter { kRays, kShadowRays, kPixels, kSkipped, kCounterCount };

/// Texel (x, y): the GBuffer pixel it stands for, `spp` cosine paths about its normal from the
/// biased position (dark and unlit pixels trace nothing), their mean radiance, the share of first
/// rays that hit within the AO radius and the mean first-hit distance.
template <class Tracer>
FP_HD void giTexel(const Frame& f, const Tracer& tracer, int x, int y,
                   WorkCounts<kCounterCount>& work) {
    const FrameSetup& s = f.setup;
    const PixelCoord p = fullResPixel(x, y, s.upscale, s.frame.width, s.frame.height);
    const double d = f.depth.at(p.x, p.y);
    const float model = f.model.at(p.x, p.y);
    const Vec3f albedo{f.baseColor[0].at(p.x, p.y), f.baseColor[1].at(p.x, p.y),
                       f.baseColor[2].at(p.x, p.y)};
    const Vec3f diffuseColor = gbufferDiffuseColor(albedo, f.metallic.at(p.x, p.y), model);
    if (!isLitSurface(d, model) ||
        ue::luma(diffuseColor.x, diffuseColor.y, diffuseColor.z) < s.diffuseThreshold) {
        for (int c = 0; c < 3; ++c) f.diffuse[c].at(x, y) = 0.0f;
        f.ao.at(x, y) = 0.0f;
        f.hitDistance.at(x, y) = -1.0f;
        ++work.value[kSkipped];
        return;
    }
    const PixelSurface surface = pixelSurface(s.camera, s.eyeOffset, p.x, p.y, d);
    const Vec3f n{f.normal[0].at(p.x, p.y), f.normal[1].at(p.x, p.y), f.normal[2].at(p.x, p.y)};
    Rng rng = Rng::fromKey(s.rngKey, p.x, p.y);
    Vec3f radiance;
    int aoHits = 0, hits = 0;
    double hitDistance = 0;
    uint32_t rays = 0, shadowRays = 0;
    for (int k = 0; k < s.spp; ++k) {
        // A cosine ray about the GBuffer normal from the biased position (§12.2).
        const float u = rng.nextFloat(), v = rng.nextFloat();
        const Vec3f dir = cosineHemisphere(n, u, v);
        const Vec3f org = biasedRayOrigin(surface, n, dot(n, dir), s.bias);
        const DiffusePath path =
            traceDiffusePath(tracer, s.paths, org, dir, s.tMin, rng, rays, shadowRays);
        radiance += path.radiance;
        if (path.firstHit >= 0.0f) {
            ++hits;
            hitDistance += path.firstHit;
            if (path.firstHit < s.aoRadius) ++aoHits;
        }
    }
    const float inv = 1.0f / float(s.spp);
    f.diffuse[0].at(x, y) = radiance.x * inv;
    f.diffuse[1].at(x, y) = radiance.y * inv;
    f.diffuse[2].at(x, y) = radiance.z * inv;
    f.ao.at(x, y) = 1.0f - float(aoHits) * inv;
    f.hitDistance.at(x, y) = hits > 0 ? float(hitDistance / hits) : -1.0f;
    work.value[kRays] += rays;
    work.value[kShadowRays] += shadowRays;
    ++work.value[kPixels];
}

/// The pass through `tracer` on either backend (PerPixel.h): the trace grid `trace` (the frame
/// divided by the upscale), every output written at every texel.
template <class Ports, class Pixels, class Tracer>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const FrameSetup& setup,
         Extent trace, const Tracer& tracer, const char* what) {
    Frame f{};
    f.setup = setup;
    f.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    f.model = viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0));
    f.metallic = viewOf(ports.input(gbuffer::kMetallic)->image().plane(0));
    for (int c = 0; c < 3; ++c) {
        f.normal[c] = viewOf(ports.input(gbuffer::kNormal)->image().plane(c));
        f.baseColor[c] = viewOf(ports.input(gbuffer::kBaseColor)->image().plane(c));
    }
    auto& diffuse = ports.overwrite(kDiffuse, {trace});
    for (int c = 0; c < 3; ++c) f.diffuse[c] = spanOf(diffuse.image().plane(c));
    f.ao = spanOf(ports.overwrite(kAo, {trace}).image().plane(0));
    f.hitDistance = spanOf(ports.overwrite(kHitDistance, {trace}).image().plane(0));
    const auto counts = pixels.template forEach<kCounterCount>(
        trace.width, trace.height,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& w) { giTexel(f, tracer, x, y, w); },
        what);
    ctx.addWork("rays", counts[kRays]);
    ctx.addWork("shadowRays", counts[kShadowRays]);
    ctx.addWork("pixels", counts[kPixels]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
}

}  // namespace fp::rtgi
