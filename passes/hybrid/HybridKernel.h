#pragma once
// The hybrid's fallback (algorithms §12.3), written once for every tracer and backend: SSGI's
// kernel (ssgi::run) marches every ray; a ray the screen cannot finish is traced from the pixel's
// surface through the scene as a diffuse path (traceDiffusePath, rt_global_illumination's), and
// with continueOnScreen an on-screen hit continues as a path from the hit pixel's GBuffer
// surface. execute() runs it with CpuPixels through Embree (EmbreeTracer) or, with traversal
// "bvh", through framepass's BVH (BvhTracer) — the code the GPU runs (HybridPass.cu).
#include "foundation/Camera.h"
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Random.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "foundation/UnrealRandom.h"
#include "passes/ssgi/SSGIKernel.h"
#include "screenspace/GBuffer.h"
#include "shading/DiffusePaths.h"
#include "shading/RayOriginBias.h"

#include <cstdint>

namespace fp::hybrid {

enum HybridCounter { kFallbackRays, kFallbackHits, kContinued, kSceneRays, kShadowRays, kHybridCounters };

/// SSGI's fallback (ssgi::NoFallback's shape) through `Tracer`.
template <class Tracer>
struct GiFallback {
    Tracer tracer;
    DiffusePathSettings paths;   // a fallback ray's path
    DiffusePathSettings onward;  // an on-screen hit's continuation (maxBounces − 1)
    bool continuing;             // continueOnScreen with bounces to continue
    CameraView cam;
    Vec3d eyeOffset;  // the camera relative to the scene's origin
    RayBias bias;
    uint32_t rngKey, onwardKey;
    bool wantDistance;
    PlaneView depth, normal[3], shadingModel, baseColor[3], metallic;  // the last two continuing
    unsigned long long* counts;  // HybridCounter, where the pixels run

    struct Pixel {
        PixelSurface surface;  // the fallback rays' common origin, as the RT passes leave it
        Vec3f n;
        Rng rng;
        // The continued paths draw from their own sequence, so the fallback rays are the same
        // with continueOnScreen as without.
        Rng onwardRng;
        uint32_t count[kHybridCounters];
    };

    FP_HD Pixel begin(const ssgi::Frame&, int x, int y) const {
        Pixel p{};
        p.surface = pixelSurface(cam, eyeOffset, x, y, depth.at(x, y));
        p.n = {normal[0].at(x, y), normal[1].at(x, y), normal[2].at(x, y)};
        p.rng = Rng::fromKey(rngKey, x, y);
        p.onwardRng = Rng::fromKey(onwardKey, x, y);
        return p;
    }
    FP_HD bool continuesHits() const { return continuing; }

    /// Where an on-screen hit's path continues from: the hit pixel's GBuffer surface (`valid`
    /// false where that pixel is unlit or sky: no path).
    struct Continuation {
        bool valid = false;
        Vec3f diffuseColor, n;
        PixelSurface surface;
    };

    /// The GBuffer pixel an on-screen hit continues from: the hit's half-resolution position,
    /// on the full-resolution GBuffer.
    FP_HD PixelCoord continuationPixel(const RayPoint& hit) const {
        const int W = depth.width, H = depth.height;
        const int hx = int(hit.hx * 2.0f), hy = int(hit.hy * 2.0f);
        return {hx < 0 ? 0 : (hx > W - 1 ? W - 1 : hx), hy < 0 ? 0 : (hy > H - 1 ? H - 1 : hy)};
    }

    FP_HD Continuation continuation(const RayPoint& hit) const {
        const PixelCoord q = continuationPixel(hit);
        const int px = q.x, py = q.y;
        const double d = depth.at(px, py);
        Continuation k;
        if (!isLitSurface(d, shadingModel.at(px, py))) return k;
        k.valid = true;
        k.diffuseColor = gbufferDiffuseColor(
            {baseColor[0].at(px, py), baseColor[1].at(px, py), baseColor[2].at(px, py)},
            metallic.at(px, py), shadingModel.at(px, py));
        k.n = normalize(Vec3f{normal[0].at(px, py), normal[1].at(px, py), normal[2].at(px, py)});
        k.surface = pixelSurface(cam, eyeOffset, px, py, d);
        return k;
    }

    /// A continuation's path: one cosine ray about the hit pixel's normal, drawn from `rng` (the
    /// pixel's onward stream).
    FP_HD PathState continuationPath(const Continuation& k, Rng& rng) const {
        const float u = rng.nextFloat(), v = rng.nextFloat();
        const Vec3f dir = cosineHemisphere(k.n, u, v);
        const Vec3f org = biasedRayOrigin(k.surface, k.n, dot(k.n, dir), bias);
        return startPath(onward, org, dir, 0.0f);
    }

    // Last frame's colour at an on-screen hit `c`, plus the hit surface's diffuse colour × one
    // cosine path of the bounces after it.
    FP_HD void onScreenHit(Pixel& p, const RayPoint& hit, float c[3]) const {
        const Continuation k = continuation(hit);
        if (!k.valid) return;
        ++p.count[kContinued];
        const DiffusePath path = traceDiffusePath(tracer, onward, continuationPath(k, p.onwardRng),
                                                  p.onwardRng, p.count[kSceneRays],
                                                  p.count[kShadowRays]);
        const Vec3f more = k.diffuseColor * path.radiance;
        c[0] += more.x, c[1] += more.y, c[2] += more.z;
    }

    /// The path of the pixel's ray `L` (view space) that the march could not finish: the same
    /// direction through the scene, from the pixel (a march that saw nothing may still have passed
    /// behind a surface).
    FP_HD PathState missPath(const Pixel& p, const Vec3f& L) const {
        const Vec3f dir = normalize(Vec3f(cam.right) * L.x + Vec3f(cam.up) * L.y + Vec3f(cam.forward) * L.z);
        const Vec3f org = biasedRayOrigin(p.surface, p.n, dot(p.n, dir), bias);
        return startPath(paths, org, dir, 0.0f);
    }

    /// What that path brings, weighted as SSGI weighs an on-screen hit, so the pixel's resolve
    /// undoes one weighting over all its hits (algorithms §4.7–4.8); nothing where it left the
    /// scene, as a miss.
    FP_HD ssgi::RayTrace missTrace(const DiffusePath& path) const {
        if (path.firstHit < 0.0f) return {};
        ssgi::RayTrace hit;
        const Vec3f c = path.radiance;
        const float karis = 1.0f / (1.0f + ue::luma(c.x, c.y, c.z));
        hit.weighted[0] = c.x * karis;
        hit.weighted[1] = c.y * karis;
        hit.weighted[2] = c.z * karis;
        hit.hit = true;
        hit.measured = wantDistance;
        hit.distance = path.firstHit;
        return hit;
    }

    FP_HD ssgi::RayTrace miss(Pixel& p, int, int, const Vec3f& L) const {
        ++p.count[kFallbackRays];
        const ssgi::RayTrace hit = missTrace(traceDiffusePath(
            tracer, paths, missPath(p, L), p.rng, p.count[kSceneRays], p.count[kShadowRays]));
        if (hit.hit) ++p.count[kFallbackHits];
        return hit;
    }

    template <class Trace>
    FP_HD void addHit(Pixel&, Trace& trace, const ssgi::RayTrace& r) const {
        trace.add(r);
    }

    FP_HD void end(Pixel& p) const {
        for (int i = 0; i < kHybridCounters; ++i)
            if (p.count[i]) addSharedCount(counts + i, p.count[i]);
    }
};

/// The GBuffer planes the fallback reads, through either backend's ports (PassPorts.h).
template <class Ports, class Fallback>
void bindPlanes(const Ports& ports, Fallback& f) {
    f.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    f.shadingModel = viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0));
    for (int c = 0; c < 3; ++c) f.normal[c] = viewOf(ports.input(gbuffer::kNormal)->image().plane(c));
    if (f.continuing) {
        for (int c = 0; c < 3; ++c)
            f.baseColor[c] = viewOf(ports.input(gbuffer::kBaseColor)->image().plane(c));
        f.metallic = viewOf(ports.input(gbuffer::kMetallic)->image().plane(0));
    }
}

}  // namespace fp::hybrid
