#pragma once
// SSR's per-pixel work (algorithms §5), written once for both backends: SSRPass::execute runs it
// with CpuPixels, SSRPass.cu with CudaPixels — the same code, the same arithmetic, the same bits.
// Two sweeps: the trace (one pixel's rays, marched through the furthest HZB), then, with
// r.SSR.Temporal, the smoothing against last frame's reflection.
#include "screenspace/GBuffer.h"
#include "screenspace/HzbMarch.h"
#include "screenspace/Reprojection.h"
#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "foundation/UnrealRandom.h"
#include "framework/Pass.h"
#include "passes/ssr/SSRPass.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace fp::ssr {

// Ports (besides the GBuffer's, gbuffer::k*).
inline constexpr const char* kFurthestHzb = "furthestHzb";
inline constexpr const char* kColor = "color";
inline constexpr const char* kReflection = "reflection";
inline constexpr const char* kHitMask = "hitMask";
inline constexpr const char* kHitDistance = "hitDistance";

constexpr float kStepOffsetBias = -0.5f;     // algorithms §4.6/§5.3: IGN − 0.5 for SSR
constexpr float kToleranceScale = 4.0f;      // algorithms §4.5: k = 4 for SSR
constexpr float kSingleRayRoughness = 0.1f;  // §5.3: below it one mirror ray
constexpr int kSingleRayMaxSteps = 24;       // §5.3: that ray's steps, min(steps·rays, 24)
/// The share of this frame in the temporal smoothing (r.SSR.Temporal): each frame moves the
/// history 1/8 of the way to the new reflection [inferred: the reference names a TAA-style pass
/// with its own history, not its weights].
constexpr float kTemporalWeight = 0.125f;

/// Work counted per pixel, in this order.
enum Counter { kTraced, kSkipped, kRough, kRays, kHzbSamples, kCounterCount };

/// Unreal's GetSSRQualityForView: the cvar capped by the post-process quality's bucket (≥ 80
/// Epic, ≥ 60 High, ≥ 40 Medium, else Low); off when the cvar is ≤ 0 or the intensity below 1.
inline SSRQuality effectiveQuality(int cvar, int postProcessQuality, float intensity) {
    if (cvar <= 0 || intensity < 1.0f) return {0, 0, 0, false};
    if (postProcessQuality >= 80 && cvar >= 4) return {4, 12, 12, true};
    if (postProcessQuality >= 60 && cvar >= 3) return {3, 8, 4, true};
    if (postProcessQuality >= 40 && cvar >= 2) return {2, 16, 1, false};
    return {1, 8, 1, false};
}

/// The roughness fade (§5.2): min(roughness · scale + 2, 1), scale = −2/maxRoughness, doubled
/// below High. A pixel whose fade is ≤ 0 is skipped.
FP_HD inline float roughnessFade(float roughness, float maxRoughness, int level) {
    float scale = -2.0f / (maxRoughness < 0.01f ? 0.01f : (maxRoughness > 1.0f ? 1.0f : maxRoughness));
    if (level < 3) scale *= 2.0f;
    const float fade = roughness * scale + 2.0f;
    return fade < 1.0f ? fade : 1.0f;
}

/// Everything one frame's pixels read and write. Absent images have null data.
struct Frame {
    ScreenRayFrame march;      //!< the quality's steps
    ScreenRayFrame singleRay;  //!< §5.3's one mirror ray of a smooth pixel: min(steps·rays, 24) steps
    CameraView previous;
    uint32_t frameMod8;
    SSRQuality quality;
    float maxRoughness, intensityScale;
    PlaneView depth, roughness, shadingModel, normal[3], color[3], customData[2];
    VelocityView velocity;
    PlaneSpan out[4], hitMask, hitDistance;
};

/// What the temporal sweep reads: this frame's unsmoothed reflection, last frame's (null without
/// a usable one) and its camera.
struct Smoothing {
    CameraView cam, historyCamera;
    PlaneView depth, current[4], history[4];
    VelocityView velocity;
    PlaneSpan out[4];
    Extent frame;
};

// The hit of one ray, read from last frame's colour (§5.4).
struct RaySample {
    bool hit = false;
    float rgb[3] = {0, 0, 0};  // vignetted radiance
    float alpha = 0;           // the vignette
    Vec3d offset;              // the hit's position relative to the eye
};

FP_HD inline RaySample shadeHit(const Frame& f, const RaySteps& steps, float time) {
    RaySample s;
    const ScreenRayFrame& g = f.march;
    const RayPoint hit = rayPointAt(steps, time);
    const double hitDepth = g.cam.depthFromDeviceZ(hit.z);
    if (!std::isfinite(hitDepth) || hitDepth <= 0.0)
        return s;
    // The hit in full-resolution pixels (centres at +0.5) and on this frame's screen.
    const double u = double(hit.hx) * 2.0, v = double(hit.hy) * 2.0;
    const int W = f.depth.width, H = f.depth.height;
    const int hx = truncToInt(std::floor(u), 0, W - 1), hy = truncToInt(std::floor(v), 0, H - 1);
    const Vec3d offset = g.cam.translatedFromPixel(u - 0.5, v - 0.5, hitDepth);
    s.offset = offset;
    // ReprojectHit: the hit texel's velocity when bound, else last frame's camera.
    const PreviousPixel prev = reprojectPixel(hx, hy, offset, g.cam.position, f.velocity, f.previous);
    const float thisVignette = vignette(float(u / W * 2.0 - 1.0), float(1.0 - v / H * 2.0));
    // A hit behind last frame's camera comes back at (−1, −1), where the vignette is 0.
    const float prevVignette = vignette(float(prev.u / W * 2.0 - 1.0), float(1.0 - prev.v / H * 2.0));
    s.alpha = thisVignette < prevVignette ? thisVignette : prevVignette;
    s.hit = true;
    if (s.alpha > 0.0f) {
        const int px = truncToInt(std::floor(prev.u), 0, W - 1);
        const int py = truncToInt(std::floor(prev.v), 0, H - 1);
        for (int c = 0; c < 3; ++c) {
            const float value = f.color[c].at(px, py);
            s.rgb[c] = (value > 0.0f && std::isfinite(value) ? value : 0.0f) * s.alpha;
        }
    }
    return s;
}

/// What a ray the screen cannot finish brings: in Unreal's SSR, nothing. (framepass's reflection
/// hybrid passes a callable of the same shape that traces the ray through the scene.)
struct NoFallback {
    FP_HD RaySample operator()(int, int, const Vec3d&, const Vec3f&, const Vec3f&, float) const {
        return {};
    }
};

/// One pixel (x, y): skipped (unlit, sky, too rough) or its rays traced, the outputs written
/// and the work added to `counts` (indexed by Counter). Outputs stay 0 where a pixel is skipped.
/// A ray whose march leaves the screen or ends without a hit asks `fallback(x, y, offset, N, L,
/// roughness)` for its sample: the pixel, its surface as an offset from the eye, its unit normal,
/// the ray's world direction.
template <class Fallback = NoFallback>
FP_HD inline void ssrPixel(const Frame& f, int x, int y, unsigned long long* counts,
                           const Fallback& fallback = {}) {
    const double d = f.depth.at(x, y);
    const float modelValue = f.shadingModel.at(x, y);
    if (!isLitSurface(d, modelValue)) {
        ++counts[kSkipped];
        return;
    }
    float roughness = f.roughness.at(x, y);
    if (truncToInt(modelValue, 0, 255) == kClearCoat && f.customData[0].data) {
        // §5.2, 4.27/5.0: the coat's roughness blended in by its amount.
        const float coat = saturate(f.customData[0].at(x, y));
        roughness += (saturate(f.customData[1].at(x, y)) - roughness) * coat;
    }
    const float fade = roughnessFade(roughness, f.maxRoughness, f.quality.level);
    if (fade <= 0.0f) {  // Unreal's stencil pre-pass: no rays, output 0
        ++counts[kRough];
        return;
    }
    ++counts[kTraced];
    // §5.3: below roughness 0.1 the glossy qualities trace one longer mirror ray.
    const bool singleRay = f.quality.glossy && roughness < kSingleRayRoughness;
    const ScreenRayFrame& g = singleRay ? f.singleRay : f.march;
    const int rays = singleRay ? 1 : f.quality.rays, steps = g.steps;
    const bool glossy = f.quality.glossy && !singleRay;
    const float levelStep = 8.0f * g.invSteps * roughness;  // §4.6: (8/N)·Roughness
    const ScreenRayOrigin o = screenRayOrigin(
        g, x, y, d,
        ue::interleavedGradientNoise(float(x) + 0.5f, float(y) + 0.5f, f.frameMod8) + kStepOffsetBias);
    const CameraView& cam = f.march.cam;
    const Vec3d pd = cam.translatedFromPixel(x, y, d);
    const Vec3f V = normalize(-Vec3f{float(pd.x), float(pd.y), float(pd.z)});
    const Vec3f N = normalize(Vec3f{f.normal[0].at(x, y), f.normal[1].at(x, y), f.normal[2].at(x, y)});
    const ue::Rand3 seed = ue::rand3DPCG16(x, y, int32_t(f.frameMod8));
    const float alpha = roughness * roughness;
    float sum[3] = {0, 0, 0}, coverage = 0, distanceSum = 0;
    int hits = 0;
    unsigned hzbSamples = 0;
    for (int r = 0; r < rays; ++r) {
        Vec3f L;
        if (glossy) {
            float e1, e2;
            ue::hammersley16(uint32_t(r), uint32_t(rays), seed.x, seed.y, e1, e2);
            L = reflect(V, sampleGgxVisibleNormal(N, V, alpha, e1, e2));
        } else {
            L = reflect(V, N);
        }
        const Vec3f Lview{float(dot(Vec3d(L), cam.right)), float(dot(Vec3d(L), cam.up)),
                          float(dot(Vec3d(L), cam.forward))};
        RaySteps raySteps;
        float level, time = 0.0f;
        const bool onScreen =
            screenRaySteps(g, o, Lview, kToleranceScale, raySteps) &&
            marchHzb(g.hzb, raySteps, steps, levelStep, level, hzbSamples, &time) >= 0;
        const RaySample s = onScreen ? shadeHit(f, raySteps, time) : fallback(x, y, pd, N, L, roughness);
        if (!s.hit) continue;
        ++hits;
        distanceSum += float(length(s.offset - pd));
        // §5.4: Karis-weight each ray when there are several.
        const float karis = rays > 1 ? 1.0f / (1.0f + ue::luma(s.rgb[0], s.rgb[1], s.rgb[2])) : 1.0f;
        for (int c = 0; c < 3; ++c) sum[c] += s.rgb[c] * karis;
        coverage += s.alpha;
    }
    counts[kRays] += (unsigned long long)rays;
    counts[kHzbSamples] += hzbSamples;
    const float inv = 1.0f / float(rays);
    float mean[3] = {sum[0] * inv, sum[1] * inv, sum[2] * inv};
    if (rays > 1) {
        const float inverseKaris = 1.0f / (1.0f - ue::luma(mean[0], mean[1], mean[2]));
        for (float& m : mean) m *= inverseKaris;
    }
    const float scale = fade * f.intensityScale;
    for (int c = 0; c < 3; ++c) f.out[c].at(x, y) = mean[c] * scale;
    f.out[3].at(x, y) = coverage * inv * scale;
    if (f.hitMask) f.hitMask.at(x, y) = float(hits) * inv;
    if (f.hitDistance && hits > 0) f.hitDistance.at(x, y) = distanceSum / float(hits);
}

/// r.SSR.Temporal at pixel (x, y): this frame's reflection moved from last frame's, reprojected
/// through the pixel's surface and clamped to the 3×3 neighbourhood of this frame's, by
/// kTemporalWeight. Pixels with no history (off screen, sky) keep this frame's; `counts[0]`
/// counts those that had one.
FP_HD inline void smoothPixel(const Smoothing& s, int x, int y, unsigned long long* counts) {
    for (int c = 0; c < 4; ++c) s.out[c].at(x, y) = s.current[c].at(x, y);
    const double d = s.depth.at(x, y);
    if (std::isinf(d) || !(d > 0.0)) return;
    const PreviousPixel prev = reprojectPixelAtDepth(s.cam, x, y, d, s.velocity, s.historyCamera);
    if (!prev.onScreen(s.frame)) return;
    const int hx = truncToInt(prev.u, 0, s.frame.width - 1), hy = truncToInt(prev.v, 0, s.frame.height - 1);
    ++counts[0];
    for (int c = 0; c < 4; ++c) {
        const float here = s.current[c].at(x, y);
        float lo = here, hi = here;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const float v = s.current[c].clampedAt(x + dx, y + dy);
                lo = v < lo ? v : lo;
                hi = v > hi ? v : hi;
            }
        const float past = s.history[c].at(hx, hy);
        const float h = past < lo ? lo : (past > hi ? hi : past);
        s.out[c].at(x, y) = h + (here - h) * kTemporalWeight;
    }
}

/// Four planes, one to be copied onto the other.
struct PlaneCopy {
    PlaneView from[4];
    PlaneSpan to[4];
};

/// Four planes copied, pixel for pixel, on either backend.
template <class Pixels, class From>
void copyPlanes(const Pixels& pixels, const From (&from)[4], const PlaneSpan (&to)[4], int W, int H) {
    PlaneCopy p;
    for (int c = 0; c < 4; ++c) {
        p.from[c] = viewOf(from[c]);
        p.to[c] = to[c];
    }
    pixels.template forEach<0>(
        W, H,
        [=] FP_HD(int x, int y, WorkCounts<0>&) {
            for (int c = 0; c < 4; ++c) p.to[c].at(x, y) = p.from[c].at(x, y);
        },
        "ssr copy");
}

/// The whole pass through `ports` (HostPorts or DevicePorts) on `pixels` (CpuPixels or
/// CudaPixels), its work reported to `ctx`.
template <class Ports, class Pixels, class Fallback = NoFallback>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const SSRQuality& quality,
         float maxRoughness, float intensity, bool temporal, const Fallback& fallback = {}) {
    const auto& depth = ports.input(gbuffer::kDepth)->image();
    const int W = depth.width(), H = depth.height();
    const std::vector<Extent> frameExtent = {{W, H}};
    auto& out = ports.output(kReflection, frameExtent);
    if (quality.level == 0) {
        // Every output stays 0: no reflection, no coverage, no hits (those asked for exist).
        ports.outputIfRequested(kHitMask, frameExtent);
        ports.outputIfRequested(kHitDistance, frameExtent);
        ctx.addWork("skippedPixels", uint64_t(W) * H);
        return;
    }
    const FrameInfo& info = ctx.frame();
    const auto& hzb = *ports.input(kFurthestHzb);
    FP_CHECK(hzb.mipCount() >= 1 && hzb.mipCount() <= kMaxHzbMips,
             "furthestHzb has {} mips; SSR reads 1 to {}", hzb.mipCount(), kMaxHzbMips);
    const auto& color = ports.input(kColor)->image();
    FP_CHECK(color.width() == W && color.height() == H,
             "the colour input is {}×{}, the frame {}×{}", color.width(), color.height(), W, H);

    Frame f{};
    f.quality = quality;
    bindScreenRayCamera(f.march, info.camera.current, W, H);
    f.march.hzb = hzbViewOf(hzb);
    f.march.steps = quality.steps;
    f.march.invSteps = 1.0f / float(f.march.steps);
    f.singleRay = f.march;
    f.singleRay.steps = std::min(quality.steps * quality.rays, kSingleRayMaxSteps);
    f.singleRay.invSteps = 1.0f / float(f.singleRay.steps);
    f.previous = info.camera.previous.value_or(info.camera.current);
    f.frameMod8 = ue::frameIndexMod8(info.number);
    f.maxRoughness = maxRoughness;
    f.intensityScale = std::clamp(intensity * 0.01f, 0.0f, 1.0f);
    f.depth = viewOf(depth.plane(0));
    f.roughness = viewOf(ports.input(gbuffer::kRoughness)->image().plane(0));
    f.shadingModel = viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0));
    const auto& normal = ports.input(gbuffer::kNormal)->image();
    for (int c = 0; c < 3; ++c) {
        f.normal[c] = viewOf(normal.plane(c));
        f.color[c] = viewOf(color.plane(c));
    }
    if (const auto* customData = ports.input(gbuffer::kCustomData))
        for (int c = 0; c < 2; ++c) f.customData[c] = viewOf(customData->image().plane(c));
    f.velocity = velocityViewOf(ports.input(gbuffer::kVelocity));
    if (auto* hitMask = ports.outputIfRequested(kHitMask, frameExtent))
        f.hitMask = spanOf(hitMask->image().plane(0));
    if (auto* hitDistance = ports.outputIfRequested(kHitDistance, frameExtent))
        f.hitDistance = spanOf(hitDistance->image().plane(0));

    // With temporal smoothing the trace goes to a working image and the smoothing writes the
    // output; without it, straight to the output.
    using TextureT = std::decay_t<decltype(out)>;
    TextureT traced;
    if (temporal) traced = ports.scratch(frameExtent, {"R", "G", "B", "A"});
    for (int c = 0; c < 4; ++c) f.out[c] = spanOf((temporal ? traced : out).image().plane(c));

    const auto counts = pixels.template forEach<kCounterCount>(
        W, H,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& n) { ssrPixel(f, x, y, n.value, fallback); },
        "ssr");
    ctx.addWork("pixels", counts[kTraced]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
    ctx.addWork("roughPixels", counts[kRough]);
    ctx.addWork("rays", counts[kRays]);
    ctx.addWork("hzbSamples", counts[kHzbSamples]);
    if (!temporal) return;

    Smoothing s{};
    s.cam = f.march.cam;
    s.frame = {W, H};
    s.depth = f.depth;
    s.velocity = f.velocity;
    for (int c = 0; c < 4; ++c) {
        s.current[c] = viewOf(traced.image().plane(c));
        s.out[c] = spanOf(out.image().plane(c));
    }
    const auto* past = ports.historyState();
    const bool hasHistory = past && past->image().width() == W && past->image().height() == H;
    if (hasHistory) {
        for (int c = 0; c < 4; ++c) s.history[c] = viewOf(past->image().plane(c));
        s.historyCamera = ctx.history()->camera;
        const auto kept = pixels.template forEach<1>(
            W, H, [=] FP_HD(int x, int y, WorkCounts<1>& n) { smoothPixel(s, x, y, n.value); },
            "ssr temporal");
        ctx.addWork("historyPixels", kept[0]);
    } else {
        copyPlanes(pixels, s.current, s.out, W, H);
    }
    // The next frame's history: this frame's smoothed reflection, in the trace's image.
    PlaneSpan state[4];
    for (int c = 0; c < 4; ++c) state[c] = spanOf(traced.image().plane(c));
    copyPlanes(pixels, s.out, state, W, H);
    ports.keepHistory(std::move(traced));
}

}  // namespace fp::ssr
