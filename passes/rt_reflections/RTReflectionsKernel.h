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

#include <array>
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

/// Unreal's RoughnessFade: 1 up to half the cutoff, 0 at it. T: float, or float lanes (each lane
/// the same operations in the same order).
template <class T>
FP_HD inline T roughnessFadeOf(T roughness, float maxRoughness) {
    const T f = T(2.0f) - T(2.0f) * roughness / T(maxRoughness);
    return ifThenElse(f < 0.0f, T(0.0f), ifThenElse(f > 1.0f, T(1.0f), f));
}
FP_HD inline float roughnessFade(float roughness, float maxRoughness) {
    return roughnessFadeOf(roughness, maxRoughness);
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

/// A texel's rays as they gather: what its set-up found and the sums its rays add to.
struct Texel {
    bool traced = false;  // false: an unlit, hair or too rough pixel, which traces nothing
    PixelSurface surface;
    Vec3f N;
    float roughness = 0, fade = 0;
    Rng rng;
    Vec3f sum;
    double distanceSum = 0;
    int hits = 0, sawSky = 0;
    uint32_t shadowRays = 0, indirectRays = 0, screenHits = 0;
};

/// Whether a GBuffer pixel of this depth, shading model and roughness traces: a lit surface, not
/// hair, smooth enough for its roughness fade to leave something. T: float, or float lanes (a
/// row's pixels, RTReflectionsLanes.cpp).
template <class T>
FP_HD inline MaskOf<T> tracesOf(T depth, T model, T roughness, float maxRoughness) {
    const IntOf<T> id = floorToIntOf(model, 0, 255);  // the buffer's value truncated, as an id
    return isLitSurfaceOf(depth, id) & !(id == kHair) &
           (roughnessFadeOf(roughness, maxRoughness) > 0.0f);
}

/// Whether the GBuffer pixel p traces (tracesOf).
FP_HD inline bool tracesAt(const Frame& f, PixelCoord p) {
    return tracesOf(f.depth.at(p.x, p.y), f.model.at(p.x, p.y), f.roughness.at(p.x, p.y),
                    f.setup.maxRoughness);
}

/// The set-up of a texel whose GBuffer pixel p traces (tracesAt).
FP_HD inline Texel tracedTexelAt(const Frame& f, PixelCoord p) {
    const FrameSetup& s = f.setup;
    Texel t;
    t.traced = true;
    t.roughness = f.roughness.at(p.x, p.y);
    t.fade = roughnessFade(t.roughness, s.maxRoughness);
    t.surface = pixelSurface(s.camera, s.eyeOffset, p.x, p.y, f.depth.at(p.x, p.y));
    t.N = {f.normal[0].at(p.x, p.y), f.normal[1].at(p.x, p.y), f.normal[2].at(p.x, p.y)};
    t.rng = Rng::fromKey(s.rngKey, p.x, p.y);
    return t;
}

/// Texel (x, y)'s set-up from the GBuffer pixel it stands for (untraced: nothing set up, since
/// writeTexel writes the skipped values for it).
FP_HD inline Texel texelAt(const Frame& f, int x, int y) {
    const FrameSetup& s = f.setup;
    const PixelCoord p = fullResPixel(x, y, s.upscale, s.frame.width, s.frame.height);
    return tracesAt(f, p) ? tracedTexelAt(f, p) : Texel{};
}

/// A reflection ray: org + t·L, t from 0.
struct ReflectionRay {
    Vec3f org, L;
};

/// A texel's next ray from its surface, normal N and roughness, drawing from `rng` (a stream's
/// state, advanced): the mirror direction below kMirrorRoughness, else drawn from its GGX lobe,
/// mirrored back above the surface where it points below. T: float, or float lanes (a wave's
/// texels a vector, RTReflectionsLanes.cpp), every lane the same operations in the same order.
template <class T>
FP_HD FP_HOT_INLINE void texelRayOf(const RayBias& bias, const PixelSurfaceOf<T>& surface,
                                    const Vec3T<T>& N, T roughness, UIntOf<T>& rng,
                                    Vec3T<T>& org, Vec3T<T>& L) {
    const Vec3T<T>& V = surface.toEye;
    const T e1 = nextFloatOf<T>(rng), e2 = nextFloatOf<T>(rng);
    const MaskOf<T> mirror = roughness < kMirrorRoughness;
    L = reflect(V, N);
    // (Each select's other side is worked out only where some lane takes it: for float, a branch.)
    if (anyLane(!mirror)) {
        // GGX visible normals with a² = roughness⁴; the disk's radius coordinate scaled by 0.9
        // leaves out the lobe's tail.
        const Vec3T<T> H = sampleGgxVisibleNormalOf<T>(N, V, roughness * roughness,
                                                       e2 * (1.0f - kImportantSampleBias), e1);
        L = ifThenElse(mirror, L, reflect(V, H));
    }
    const T NoL = dot(N, L);
    const MaskOf<T> below = NoL < 0.0f;
    if (anyLane(below)) L = ifThenElse(below, normalize(L - N * (2.0f * NoL)), L);  // mirrored back above
    org = biasedRayOrigin(surface.p, surface.toEye, surface.eyeDistance, N, dot(N, L), bias.max,
                          bias.min);
}

/// The texel's next ray (texelRayOf).
FP_HD inline ReflectionRay texelRay(const FrameSetup& s, Texel& t) {
    ReflectionRay r;
    uint32_t state = t.rng.state();
    texelRayOf<float>(s.bias, t.surface, t.N, t.roughness, state, r.org, r.L);
    t.rng = Rng::resume(state);
    return r;
}

/// The ray found `hit` (or nothing): a miss takes the sky's cubemap, a hybrid's hit on screen the
/// lit colour there. True when the hit is left to be lit (seenFrom, then lightReflectionHit).
FP_HD inline bool reachHit(const Frame& f, Texel& t, const ReflectionRay& r, const PathHit& hit) {
    if (!hit.hit) {
        if (f.sky.on) {
            t.sum += f.sky.cube.sample(r.L, f.sky.cube.mipForRoughness(t.roughness));
            ++t.sawSky;
        }
        return false;
    }
    ++t.hits;
    t.distanceSum += hit.t;
    if (!f.sceneColor[0].data) return true;
    // Unreal's hybrid: on screen, in front of the camera, and at most 5 cm behind the depth
    // buffer there: the lit colour of that pixel, point sampled, no shading.
    const FrameSetup& s = f.setup;
    const Vec3f hitPoint = r.org + r.L * hit.t;  // relative to the scene's origin
    const CameraView::Projection pr = s.camera.projectOffset(Vec3d(hitPoint), s.origin);
    if (pr.depth > 0.0 && pr.px >= 0.0 && pr.py >= 0.0 && pr.px < s.frame.width &&
        pr.py < s.frame.height) {
        const int hx = int(pr.px), hy = int(pr.py);
        const double there = f.depth.at(hx, hy);
        if (std::isfinite(there) && pr.depth - there < s.hybridDepth) {
            t.sum += Vec3f{f.sceneColor[0].at(hx, hy), f.sceneColor[1].at(hx, hy),
                           f.sceneColor[2].at(hx, hy)};
            ++t.screenHits;
            return false;
        }
    }
    return true;
}

/// A hit's shading point made the point it is lit at: the hybrid's seen from the camera, so
/// both kinds of hit match (knowingly wrong for the specular term, as in Unreal).
FP_HD inline void seenFrom(const Frame& f, const ReflectionRay& r, PathHit& hit) {
    if (f.sceneColor[0].data)
        hit.surface.toViewer = normalize(Vec3f(f.setup.eyeOffset) - (r.org + r.L * hit.t));
}

/// Texel (x, y)'s outputs where it traced nothing: no reflection, no coverage, hit distance −2.
FP_HD inline void writeSkipped(const Frame& f, int x, int y) {
    for (int c = 0; c < 4; ++c) f.reflection[c].at(x, y) = 0.0f;
    f.hitDistance.at(x, y) = -2.0f;
}

/// Texel (x, y)'s outputs — the faded mean with its coverage and the mean hit distance (the
/// skipped values where it traced nothing) — and its counts.
FP_HD inline void writeTexel(const Frame& f, const Texel& t, int x, int y,
                             WorkCounts<kCounterCount>& work) {
    if (!t.traced) {
        writeSkipped(f, x, y);
        ++work.value[kSkipped];
        return;
    }
    const int spp = f.setup.spp;
    const float scale = t.fade / float(spp);
    f.reflection[0].at(x, y) = t.sum.x * scale;
    f.reflection[1].at(x, y) = t.sum.y * scale;
    f.reflection[2].at(x, y) = t.sum.z * scale;
    // Coverage: the samples that found something (a surface, or the sky); a miss with no sky
    // light leaves its share to the reflection captures.
    f.reflection[3].at(x, y) = t.fade * float(t.hits + t.sawSky) / float(spp);
    f.hitDistance.at(x, y) =
        t.hits > 0 ? float(t.distanceSum / t.hits) : (t.sawSky > 0 ? kSkyHitDistance : -1.0f);
    work.value[kRays] += uint32_t(spp);
    work.value[kShadowRays] += t.shadowRays;
    work.value[kIndirectRays] += t.indirectRays;
    work.value[kSkyRays] += uint32_t(t.sawSky);
    work.value[kScreenHits] += t.screenHits;
    ++work.value[kPixels];
}

/// Texel (x, y): its set-up, `spp` reflection rays one after another, each hit lit with its
/// shadow rays traced one at a time, its outputs.
template <class Tracer>
FP_HD void reflectionTexel(const Frame& f, const Tracer& tracer, int x, int y,
                           WorkCounts<kCounterCount>& work) {
    const FrameSetup& s = f.setup;
    Texel t = texelAt(f, x, y);
    if (t.traced) {
        for (int k = 0; k < s.spp; ++k) {
            const ReflectionRay r = texelRay(s, t);
            PathHit hit =
                tracer.closestHit(r.org, r.L, 0.0f, std::numeric_limits<float>::infinity());
            if (!reachHit(f, t, r, hit)) continue;
            seenFrom(f, r, hit);
            t.sum += lightReflectionHit(tracer, hit.surface, f.sky.on ? &f.sky.sh : nullptr,
                                        s.shadowed, s.lightSamples, s.indirectBounces, t.rng,
                                        t.shadowRays, t.indirectRays);
        }
    }
    writeTexel(f, t, x, y, work);
}

/// The frame's planes from `ports` (HostPorts or DevicePorts), its outputs made for the trace
/// grid `trace`; the hybrid's reads `sceneColor`.
template <class Ports>
Frame frameOf(const Ports& ports, const FrameSetup& setup, const Sky& sky, Extent trace,
              bool hybrid) {
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
    return f;
}

/// The run report's counts.
inline void addWork(PassContext& ctx, const std::array<uint64_t, kCounterCount>& counts,
                    const FrameSetup& setup, bool hybrid) {
    ctx.addWork("rays", counts[kRays]);
    ctx.addWork("shadowRays", counts[kShadowRays]);
    if (setup.indirectBounces > 0) ctx.addWork("indirectRays", counts[kIndirectRays]);
    ctx.addWork("skyRays", counts[kSkyRays]);
    if (hybrid) ctx.addWork("screenHits", counts[kScreenHits]);
    ctx.addWork("pixels", counts[kPixels]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
}

/// The pass through `tracer` on either backend (PerPixel.h) over the trace grid `trace`; `sky`
/// as the pixels read it (its cubemap's texels where they run).
template <class Ports, class Pixels, class Tracer>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const FrameSetup& setup,
         const Sky& sky, Extent trace, const Tracer& tracer, bool hybrid, const char* what) {
    const Frame f = frameOf(ports, setup, sky, trace, hybrid);
    const auto counts = pixels.template forEach<kCounterCount>(
        trace.width, trace.height,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& w) { reflectionTexel(f, tracer, x, y, w); },
        what);
    addWork(ctx, counts, setup, hybrid);
}

}  // namespace fp::rtr
