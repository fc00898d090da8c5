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

    // Last frame's colour at an on-screen hit `c`, plus the hit surface's diffuse colour × one
    // cosine path of the bounces after it.
    FP_HD void onScreenHit(Pixel& p, const RayPoint& hit, float c[3]) const {
        // The hit's half-resolution position, on the full-resolution GBuffer.
        const int W = depth.width, H = depth.height;
        const int hx = int(hit.hx * 2.0f), hy = int(hit.hy * 2.0f);
        const int px = hx < 0 ? 0 : (hx > W - 1 ? W - 1 : hx);
        const int py = hy < 0 ? 0 : (hy > H - 1 ? H - 1 : hy);
        const double d = depth.at(px, py);
        if (!isLitSurface(d, shadingModel.at(px, py))) return;
        const Vec3f diffuseColor = gbufferDiffuseColor(
            {baseColor[0].at(px, py), baseColor[1].at(px, py), baseColor[2].at(px, py)},
            metallic.at(px, py), shadingModel.at(px, py));
        const Vec3f hn = normalize(Vec3f{normal[0].at(px, py), normal[1].at(px, py), normal[2].at(px, py)});
        const float u = p.onwardRng.nextFloat(), v = p.onwardRng.nextFloat();
        const Vec3f dir = cosineHemisphere(hn, u, v);
        const Vec3f org = biasedRayOrigin(pixelSurface(cam, eyeOffset, px, py, d), hn, dot(hn, dir), bias);
        ++p.count[kContinued];
        const DiffusePath path = traceDiffusePath(tracer, onward, org, dir, 0.0f, p.onwardRng,
                                                  p.count[kSceneRays], p.count[kShadowRays]);
        const Vec3f more = diffuseColor * path.radiance;
        c[0] += more.x, c[1] += more.y, c[2] += more.z;
    }

    // The march found nothing: the same direction through the scene, from the pixel (a march
    // that saw nothing may still have passed behind a surface).
    FP_HD ssgi::RayTrace miss(Pixel& p, int, int, const Vec3f& L) const {
        ++p.count[kFallbackRays];
        const Vec3f dir = normalize(Vec3f(cam.right) * L.x + Vec3f(cam.up) * L.y + Vec3f(cam.forward) * L.z);
        const Vec3f org = biasedRayOrigin(p.surface, p.n, dot(p.n, dir), bias);
        const DiffusePath path = traceDiffusePath(tracer, paths, org, dir, 0.0f, p.rng,
                                                  p.count[kSceneRays], p.count[kShadowRays]);
        if (path.firstHit < 0.0f) return {};  // left the scene: no light, as a miss
        ++p.count[kFallbackHits];
        // Weighted as SSGI weighs an on-screen hit, so the pixel's resolve undoes one weighting
        // over all its hits (algorithms §4.7–4.8).
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
