#pragma once
// rt_reflections' per-texel work (algorithms §12.4), written once for every tracer and backend:
// a texel's set-up from the GBuffer pixel it stands for, its mirror or GGX rays, each hit taken
// from the screen (the hybrid) or lit (lightReflectionHit), each miss the sky light's cubemap,
// the resolve. execute() runs it with CpuPixels through Embree's scene (EmbreeTracer) or, with
// traversal "bvh", through framepass's BVH (BvhTracer) — the code the GPU runs with CudaPixels
// (RTReflectionsPass.cu).
#include "foundation/Camera.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Random.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "framework/Pass.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Surface.h"
#include "shading/Cubemap.h"
#include "shading/DiffusePaths.h"
#include "shading/RayOriginBias.h"
#include "shading/ReflectionHits.h"
#include "shading/SphericalHarmonics.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>

namespace fp::rtr {

inline constexpr const char* kReflection = "reflection";
inline constexpr const char* kHitDistance = "hitDistance";
inline constexpr const char* kSceneColor = "sceneColor";
constexpr float kMirrorRoughness = 0.001f;    // below it the ray is the mirror direction
constexpr float kImportantSampleBias = 0.1f;  // GGX_IMPORTANT_SAMPLE_BIAS: the tail left out
constexpr float kSkyHitDistance = 1e20f;      // Unreal's hit distance for a ray that saw the sky
constexpr float kHybridDepthCm = 5.0f;  // hybrid: a hit this close behind the depth buffer is the pixel's

/// Unreal's RoughnessFade: 1 up to half the cutoff, 0 at it.
FP_HD inline float roughnessFade(float roughness, float maxRoughness) {
    const float f = 2.0f - 2.0f * roughness / maxRoughness;
    return f < 0.0f ? 0.0f : (f > 1.0f ? 1.0f : f);
}

/// What every texel of a frame shares.
struct FrameSetup {
    CameraView camera;
    Vec3d eyeOffset;  // the eye relative to the RayScene origin
    Vec3d origin;     // the RayScene origin (a hit projected on screen)
    Extent frame;     // the GBuffer's pixels
    int upscale;      // a texel stands for the top-left pixel of its upscale × upscale block
    int spp;
    float maxRoughness;
    RayBias bias;
    float hybridDepth;  // scene units
    bool shadowed;      // one shadow ray a light at a hit
    int lightSamples;   // samples of a light with extent at a hit
    int indirectBounces;  // a hit's traced indirect light (0: the sky's SH)
    uint32_t rngKey;
};

/// The sky light as reflection rays see it, where the pixels read it (absent: `on` false).
struct Sky {
    bool on = false;
    CubemapView cube;  // a miss
    SH3 sh;            // a hit's diffuse
};

/// The sky light as the pixels read it, its cubemap's texels where they run (`texels` keeps a
/// device copy alive until the pixels are done; on the host they are the cubemap's own); off
/// without a sky light.
template <class Ports>
Sky skyFor(const Ports& ports, const ReflectedSky* sky, std::shared_ptr<const Vec3f>& texels) {
    if (!sky) return {};
    const Cubemap& cube = sky->cube;
    texels = ports.constants(cube.texels().data(), cube.texels().size());
    return {true, cube.view().rebased(cube.texels().data(), texels.get()), sky->sh};
}

/// The frame's planes, as the texels read and write them.
struct Frame {
    FrameSetup setup;
    Sky sky;
    PlaneView depth, model, normal[3], roughness;
    PlaneView sceneColor[3];  // the hybrid's (null otherwise)
    PlaneSpan reflection[4], hitDistance;
};

enum Counter {
    kRays,
    kShadowRays,
    kIndirectRays,
    kSkyRays,
    kScreenHits,
    kPixels,
    kSkipped,
    kCounterCount
};

/// Texel (x, y): the GBuffer pixel it stands for (unlit, hair and too rough pixels trace
/// nothing), `spp` reflection rays of its GGX lobe, what each brings back, the faded mean with its
/// coverage and the mean hit distance.
template <class Tracer>
FP_HD void reflectionTexel(const Frame& f, const Tracer& tracer, int x, int y,
                           WorkCounts<kCounterCount>& work) {
    const FrameSetup& s = f.setup;
    const PixelCoord p = fullResPixel(x, y, s.upscale, s.frame.width, s.frame.height);
    const double d = f.depth.at(p.x, p.y);
    const float model = f.model.at(p.x, p.y);
    const float roughness = f.roughness.at(p.x, p.y);
    const float fade = roughnessFade(roughness, s.maxRoughness);
    if (!isLitSurface(d, model) || truncToInt(model, 0, 255) == kHair || fade <= 0.0f) {
        for (int c = 0; c < 4; ++c) f.reflection[c].at(x, y) = 0.0f;
        f.hitDistance.at(x, y) = -2.0f;
        ++work.value[kSkipped];
        return;
    }
    const PixelSurface surface = pixelSurface(s.camera, s.eyeOffset, p.x, p.y, d);
    const Vec3f& V = surface.toEye;
    const Vec3f N{f.normal[0].at(p.x, p.y), f.normal[1].at(p.x, p.y), f.normal[2].at(p.x, p.y)};
    Rng rng = Rng::fromKey(s.rngKey, p.x, p.y);
    Vec3f sum;
    double distanceSum = 0;
    int hits = 0, sawSky = 0;
    uint32_t shadowRays = 0, indirectRays = 0, screenHits = 0;
    for (int k = 0; k < s.spp; ++k) {
        const float e1 = rng.nextFloat(), e2 = rng.nextFloat();
        Vec3f L;
        if (roughness < kMirrorRoughness) {
            L = reflect(V, N);
        } else {
            // GGX visible normals with a² = roughness⁴; the disk's radius coordinate scaled by
            // 0.9 leaves out the lobe's tail.
            const Vec3f H = sampleGgxVisibleNormal(N, V, roughness * roughness,
                                                   e2 * (1.0f - kImportantSampleBias), e1);
            L = reflect(V, H);
        }
        const float NoL = dot(N, L);
        if (NoL < 0.0f) L = normalize(L - N * (2.0f * NoL));  // mirrored back above
        const Vec3f org = biasedRayOrigin(surface, N, dot(N, L), s.bias);
        const PathHit hit =
            tracer.closestHit(org, L, 0.0f, std::numeric_limits<float>::infinity());
        if (!hit.hit) {
            if (f.sky.on) {
                sum += f.sky.cube.sample(L, f.sky.cube.mipForRoughness(roughness));
                ++sawSky;
            }
            continue;
        }
        ++hits;
        distanceSum += hit.t;
        const Vec3f hitPoint = org + L * hit.t;  // relative to the scene's origin
        if (f.sceneColor[0].data) {
            // Unreal's hybrid: on screen, in front of the camera, and at most 5 cm behind the
            // depth buffer there: the lit colour of that pixel, point sampled, no shading.
            const CameraView::Projection pr = s.camera.projectOffset(Vec3d(hitPoint), s.origin);
            if (pr.depth > 0.0 && pr.px >= 0.0 && pr.py >= 0.0 && pr.px < s.frame.width &&
                pr.py < s.frame.height) {
                const int hx = int(pr.px), hy = int(pr.py);
                const double there = f.depth.at(hx, hy);
                if (std::isfinite(there) && pr.depth - there < s.hybridDepth) {
                    sum += Vec3f{f.sceneColor[0].at(hx, hy), f.sceneColor[1].at(hx, hy),
                                 f.sceneColor[2].at(hx, hy)};
                    ++screenHits;
                    continue;
                }
            }
        }
        SurfacePoint lit = hit.surface;
        // Hybrid: shaded hits look from the camera, so both kinds match (knowingly wrong for the
        // specular term, as in Unreal).
        if (f.sceneColor[0].data) lit.toViewer = normalize(Vec3f(s.eyeOffset) - hitPoint);
        sum += lightReflectionHit(tracer, lit, f.sky.on ? &f.sky.sh : nullptr, s.shadowed,
                                  s.lightSamples, s.indirectBounces, rng, shadowRays,
                                  indirectRays);
    }
    const float scale = fade / float(s.spp);
    f.reflection[0].at(x, y) = sum.x * scale;
    f.reflection[1].at(x, y) = sum.y * scale;
    f.reflection[2].at(x, y) = sum.z * scale;
    // Coverage: the samples that found something (a surface, or the sky); a miss with no sky
    // light leaves its share to the reflection captures.
    f.reflection[3].at(x, y) = fade * float(hits + sawSky) / float(s.spp);
    f.hitDistance.at(x, y) =
        hits > 0 ? float(distanceSum / hits) : (sawSky > 0 ? kSkyHitDistance : -1.0f);
    work.value[kRays] += uint32_t(s.spp);
    work.value[kShadowRays] += shadowRays;
    work.value[kIndirectRays] += indirectRays;
    work.value[kSkyRays] += uint32_t(sawSky);
    work.value[kScreenHits] += screenHits;
    ++work.value[kPixels];
}

/// The pass through `tracer` on either backend (PerPixel.h) over the trace grid `trace`; `sky`
/// as the pixels read it (its cubemap's texels where they run).
template <class Ports, class Pixels, class Tracer>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const FrameSetup& setup,
         const Sky& sky, Extent trace, const Tracer& tracer, bool hybrid, const char* what) {
    Frame f{};
    f.setup = setup;
    f.sky = sky;
    f.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    f.model = viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0));
    f.roughness = viewOf(ports.input(gbuffer::kRoughness)->image().plane(0));
    for (int c = 0; c < 3; ++c) {
        f.normal[c] = viewOf(ports.input(gbuffer::kNormal)->image().plane(c));
        if (hybrid) f.sceneColor[c] = viewOf(ports.input(kSceneColor)->image().plane(c));
    }
    auto& reflection = ports.overwrite(kReflection, {trace});
    for (int c = 0; c < 4; ++c) f.reflection[c] = spanOf(reflection.image().plane(c));
    f.hitDistance = spanOf(ports.overwrite(kHitDistance, {trace}).image().plane(0));
    const auto counts = pixels.template forEach<kCounterCount>(
        trace.width, trace.height,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& w) { reflectionTexel(f, tracer, x, y, w); },
        what);
    ctx.addWork("rays", counts[kRays]);
    ctx.addWork("shadowRays", counts[kShadowRays]);
    if (setup.indirectBounces > 0) ctx.addWork("indirectRays", counts[kIndirectRays]);
    ctx.addWork("skyRays", counts[kSkyRays]);
    if (hybrid) ctx.addWork("screenHits", counts[kScreenHits]);
    ctx.addWork("pixels", counts[kPixels]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
}

}  // namespace fp::rtr
