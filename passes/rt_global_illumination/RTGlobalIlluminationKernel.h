#pragma once
// rt_global_illumination's per-texel work (algorithms §12.2), written once for every tracer and
// backend: a texel's set-up from the GBuffer pixel it stands for, its cosine paths one ray a step
// (tracePathStep), the resolve. execute() runs it with CpuPixels through Embree's scene
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

/// A texel's paths as they gather: what its set-up found and the sums its paths add to.
struct Texel {
    bool traced = false;  // false: a dark, unlit or sky pixel, which traces nothing
    PixelSurface surface;
    Vec3f n;
    Rng rng;
    Vec3f radiance;
    int aoHits = 0, hits = 0;
    double hitDistance = 0;
};

/// Texel (x, y)'s set-up from the GBuffer pixel it stands for.
FP_HD inline Texel texelAt(const Frame& f, int x, int y) {
    const FrameSetup& s = f.setup;
    const PixelCoord p = fullResPixel(x, y, s.upscale, s.frame.width, s.frame.height);
    const double d = f.depth.at(p.x, p.y);
    const float model = f.model.at(p.x, p.y);
    const Vec3f albedo{f.baseColor[0].at(p.x, p.y), f.baseColor[1].at(p.x, p.y),
                       f.baseColor[2].at(p.x, p.y)};
    const Vec3f diffuseColor = gbufferDiffuseColor(albedo, f.metallic.at(p.x, p.y), model);
    Texel t;
    if (!isLitSurface(d, model) ||
        ue::luma(diffuseColor.x, diffuseColor.y, diffuseColor.z) < s.diffuseThreshold)
        return t;
    t.traced = true;
    t.surface = pixelSurface(s.camera, s.eyeOffset, p.x, p.y, d);
    t.n = {f.normal[0].at(p.x, p.y), f.normal[1].at(p.x, p.y), f.normal[2].at(p.x, p.y)};
    t.rng = Rng::fromKey(s.rngKey, p.x, p.y);
    return t;
}

/// The texel's next path: a cosine ray about the GBuffer normal from the biased position (§12.2).
FP_HD inline PathState texelPath(const FrameSetup& s, Texel& t) {
    const float u = t.rng.nextFloat(), v = t.rng.nextFloat();
    const Vec3f dir = cosineHemisphere(t.n, u, v);
    const Vec3f org = biasedRayOrigin(t.surface, t.n, dot(t.n, dir), s.bias);
    return startPath(s.paths, org, dir, s.tMin);
}

/// A finished path's share of the texel's sums.
FP_HD inline void addPath(const FrameSetup& s, Texel& t, const DiffusePath& path) {
    t.radiance += path.radiance;
    if (path.firstHit >= 0.0f) {
        ++t.hits;
        t.hitDistance += path.firstHit;
        if (path.firstHit < s.aoRadius) ++t.aoHits;
    }
}

/// Texel (x, y)'s outputs: its paths' mean radiance, the share of first rays that hit within
/// the AO radius and the mean first-hit distance (the skipped values where it traced nothing).
FP_HD inline void writeTexel(const Frame& f, const Texel& t, int x, int y) {
    if (!t.traced) {
        for (int c = 0; c < 3; ++c) f.diffuse[c].at(x, y) = 0.0f;
        f.ao.at(x, y) = 0.0f;
        f.hitDistance.at(x, y) = -1.0f;
        return;
    }
    const float inv = 1.0f / float(f.setup.spp);
    f.diffuse[0].at(x, y) = t.radiance.x * inv;
    f.diffuse[1].at(x, y) = t.radiance.y * inv;
    f.diffuse[2].at(x, y) = t.radiance.z * inv;
    f.ao.at(x, y) = 1.0f - float(t.aoHits) * inv;
    f.hitDistance.at(x, y) = t.hits > 0 ? float(t.hitDistance / t.hits) : -1.0f;
}

/// A traced texel's work in flight: its sums, the path it traces now and how many it has begun.
struct TexelWork {
    Texel texel;
    PathState path;
    int x = 0, y = 0, paths = 0;
};

/// The texel's next path when it has one to trace; otherwise its outputs written. False when the
/// texel is done.
FP_HD inline bool nextPath(const Frame& f, TexelWork& w) {
    if (w.paths == f.setup.spp) {
        writeTexel(f, w.texel, w.x, w.y);
        return false;
    }
    w.path = texelPath(f.setup, w.texel);
    ++w.paths;
    return true;
}

/// Texel (x, y)'s set-up and its first path (forEachInSteps' begin); a texel that traces nothing
/// writes its outputs here. False when the texel is done.
FP_HD inline bool beginTexel(const Frame& f, int x, int y, TexelWork& w,
                             WorkCounts<kCounterCount>& work) {
    w.texel = texelAt(f, x, y);
    w.x = x;
    w.y = y;
    if (!w.texel.traced) {
        writeTexel(f, w.texel, x, y);
        ++work.value[kSkipped];
        return false;
    }
    ++work.value[kPixels];
    return nextPath(f, w);
}

/// One ray of the texel's path (forEachInSteps' step); a path that ends adds itself to the texel,
/// which then begins its next path or, its `spp` paths traced one after another, writes its
/// outputs. False when the texel is done.
template <class Tracer>
FP_HD bool texelStep(const Frame& f, const Tracer& tracer, TexelWork& w,
                     WorkCounts<kCounterCount>& work) {
    if (!w.path.done)
        tracePathStep(tracer, f.setup.paths, w.path, w.texel.rng, work.value[kRays],
                      work.value[kShadowRays]);
    if (!w.path.done) return true;
    addPath(f.setup, w.texel, w.path.out);
    return nextPath(f, w);
}

/// The frame's planes from `ports` (HostPorts or DevicePorts), its outputs made for the trace
/// grid `trace`.
template <class Ports>
Frame frameOf(const Ports& ports, const FrameSetup& setup, Extent trace) {
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
    return f;
}

/// The pass through `tracer` on either backend (PerPixel.h): the trace grid `trace` (the frame
/// divided by the upscale), every output written at every texel.
template <class Ports, class Pixels, class Tracer>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const FrameSetup& setup,
         Extent trace, const Tracer& tracer, const char* what) {
    const Frame f = frameOf(ports, setup, trace);
    const auto counts = pixels.template forEachInSteps<kCounterCount, TexelWork>(
        trace.width, trace.height,
        [=] FP_HD(int x, int y, TexelWork& w, WorkCounts<kCounterCount>& c) {
            return beginTexel(f, x, y, w, c);
        },
        [=] FP_HD(TexelWork& w, WorkCounts<kCounterCount>& c) { return texelStep(f, tracer, w, c); },
        what);
    ctx.addWork("rays", counts[kRays]);
    ctx.addWork("shadowRays", counts[kShadowRays]);
    ctx.addWork("pixels", counts[kPixels]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
}

}  // namespace fp::rtgi
