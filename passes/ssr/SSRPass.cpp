#include "passes/ssr/SSRPass.h"

#include "screenspace/GBuffer.h"
#include "screenspace/HzbMarch.h"
#include "screenspace/Reprojection.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "foundation/Tiles.h"
#include "foundation/UnrealRandom.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kFurthestHzb = "furthestHzb";
constexpr const char* kColor = "color";
constexpr const char* kVelocity = "velocity";
constexpr const char* kReflection = "reflection";
constexpr const char* kHitMask = "hitMask";
constexpr const char* kHitDistance = "hitDistance";

constexpr float kStepOffsetBias = -0.5f;  // algorithms §4.6/§5.3: IGN − 0.5 for SSR
constexpr float kToleranceScale = 4.0f;   // algorithms §4.5: k = 4 for SSR
constexpr float kSingleRayRoughness = 0.1f;  // §5.3: below it one mirror ray
constexpr int kSingleRayMaxSteps = 24;       // §5.3: that ray's steps, min(steps·rays, 24)

enum Counter { kTraced, kSkipped, kRough, kRays, kHzbSamples, kCounterCount };

// Everything one frame's pixels read.
struct Frame {
    ScreenRayFrame march;       // the quality's steps
    ScreenRayFrame singleRay;   // §5.3's one mirror ray of a smooth pixel: min(steps·rays, 24) steps
    CameraView previous;
    uint32_t frameMod8;
    SSRQuality quality;
    float maxRoughness, intensityScale;
    const Plane *depth, *roughness, *shadingModel;
    const Image *normal, *color, *customData = nullptr;
    VelocityView velocity;
};

// The hit of one ray, read from last frame's colour (§5.4).
struct RaySample {
    bool hit = false;
    float rgb[3] = {0, 0, 0};  // vignetted radiance
    float alpha = 0;           // the vignette
    Vec3d offset;              // the hit's position relative to the eye
};

// A copy with pixels of its own.
Image copyOf(const Image& im) {
    Image copy(im.width(), im.height(), im.channels());
    copyPixels(im, copy);
    return copy;
}

// r.SSR.Temporal: `out` (this frame's reflection) moved from last frame's, reprojected through
// each pixel's surface and clamped to the 3×3 neighbourhood of this frame's, by kTemporalWeight.
// Pixels with no history (off screen, sky) keep this frame's. Returns the pixels that had one.
uint64_t smoothTemporally(Image& out, const Image& history, const CameraView& historyCamera,
                          const CameraView& cam, const Plane& depth, const VelocityView& velocity) {
    const int W = out.width(), H = out.height();
    const Image current = copyOf(out);  // the neighbourhood is this frame's, unsmoothed
    std::atomic<uint64_t> kept{0};
    forEachTile(W, H, [&](const Tile& t) {
        uint64_t n = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const double d = depth.at(x, y);
                if (std::isinf(d) || !(d > 0.0)) continue;
                const PreviousPixel prev = reprojectPixelAtDepth(cam, x, y, d, velocity, historyCamera);
                if (!prev.onScreen({W, H})) continue;
                const int hx = std::clamp(int(prev.u), 0, W - 1), hy = std::clamp(int(prev.v), 0, H - 1);
                ++n;
                for (int c = 0; c < 4; ++c) {
                    float lo = current.plane(c).at(x, y), hi = lo;
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            const float v = current.plane(c).clampedAt(x + dx, y + dy);
                            lo = std::min(lo, v);
                            hi = std::max(hi, v);
                        }
                    const float h = std::clamp(history.plane(c).at(hx, hy), lo, hi);
                    out.plane(c).at(x, y) = h + (current.plane(c).at(x, y) - h) * SSRPass::kTemporalWeight;
                }
            }
        kept += n;
    });
    return kept;
}

RaySample shadeHit(const Frame& f, const RaySteps& steps, float time) {
    RaySample s;
    const ScreenRayFrame& g = f.march;
    const RayPoint hit = rayPointAt(steps, time);
    const double hitDepth = g.cam.depthFromDeviceZ(hit.z);
    if (!std::isfinite(hitDepth) || hitDepth <= 0.0)
        return s;
    // The hit in full-resolution pixels (centres at +0.5) and on this frame's screen.
    const double u = double(hit.hx) * 2.0, v = double(hit.hy) * 2.0;
    const int W = f.color->width(), H = f.color->height();
    const int hx = std::clamp(int(std::floor(u)), 0, W - 1), hy = std::clamp(int(std::floor(v)), 0, H - 1);
    const Vec3d offset = g.cam.translatedFromPixel(u - 0.5, v - 0.5, hitDepth);
    s.offset = offset;
    // ReprojectHit: the hit texel's velocity when bound, else last frame's camera.
    const PreviousPixel prev = reprojectPixel(hx, hy, offset, g.cam.position, f.velocity, f.previous);
    const float thisVignette = vignette(float(u / W * 2.0 - 1.0), float(1.0 - v / H * 2.0));
    // A hit behind last frame's camera comes back at (−1, −1), where the vignette is 0.
    const float prevVignette = vignette(float(prev.u / W * 2.0 - 1.0), float(1.0 - prev.v / H * 2.0));
    s.alpha = std::min(thisVignette, prevVignette);
    s.hit = true;
    if (s.alpha > 0.0f) {
        const int px = std::clamp(int(std::floor(prev.u)), 0, W - 1);
        const int py = std::clamp(int(std::floor(prev.v)), 0, H - 1);
        for (int c = 0; c < 3; ++c) {
            const float value = f.color->plane(c).at(px, py);
            s.rgb[c] = (value > 0.0f && std::isfinite(value) ? value : 0.0f) * s.alpha;
        }
    }
    return s;
}

}  // namespace

ParamSpec<SSRParams> SSRPass::paramSpec() {
    ParamSpec<SSRParams> s;
    s.add("quality", &Params::quality,
          "0 off; 1 Low (8 steps, 1 mirror ray), 2 Medium (16, 1 mirror), 3 High (8 steps × 4 GGX "
          "rays), 4 Epic (12 × 12); capped by postProcessQuality")
        .range(0, 4)
        .cvar("r.SSR.Quality");
    s.add("postProcessQuality", &Params::postProcessQuality,
          "post-process ScreenSpaceReflectionQuality: ≥ 80 allows Epic, ≥ 60 High, ≥ 40 Medium "
          "(Unreal's default 50 caps SSR at Medium)")
        .range(0, 100);
    s.add("maxRoughness", &Params::maxRoughness,
          "post-process ScreenSpaceReflectionMaxRoughness: the fade reaches 0 here (half of it "
          "below High); rougher pixels are skipped")
        .range(0.01, 1.0)
        .cvar("r.SSR.MaxRoughness");
    s.add("intensity", &Params::intensity,
          "post-process ScreenSpaceReflectionIntensity (percent); below 1 SSR is off")
        .range(0.0, 100.0);
    s.add("temporal", &Params::temporal,
          "smooth the reflection across frames: last frame's, reprojected and clamped to this "
          "frame's 3×3 neighbourhood, moves 1/8 of the way to this frame's")
        .needsHistory()
        .cvar("r.SSR.Temporal");
    return s;
}

SSRQuality SSRPass::effectiveQuality(int cvar, int pp, float intensity) {
    if (cvar <= 0 || intensity < 1.0f) return {0, 0, 0, false};
    if (pp >= 80 && cvar >= 4) return {4, 12, 12, true};
    if (pp >= 60 && cvar >= 3) return {3, 8, 4, true};
    if (pp >= 40 && cvar >= 2) return {2, 16, 1, false};
    return {1, 8, 1, false};
}

float SSRPass::roughnessFade(float roughness, float maxRoughness, int level) {
    float scale = -2.0f / std::clamp(maxRoughness, 0.01f, 1.0f);
    if (level < 3) scale *= 2.0f;
    return std::min(roughness * scale + 2.0f, 1.0f);
}

PassIO SSRPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::depthInput("linear view depth"),
        gbuffer::normalInput(),
        gbuffer::roughnessInput("roughness: the fade, the rays' lobe and mip schedule"),
        gbuffer::shadingModelInput("shading model id (unlit skipped; clear coat blends roughness)"),
        gbuffer::customDataInput("clear coat amount and roughness (R, G)", true),
        {.name = kFurthestHzb, .channels = {"Y"}, .doc = "furthest HZB (hzb.furthest)"},
        {.name = kColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .captureDefault = "PrevSceneColor",
         .doc = "last frame's colour the hits read (Unreal reads its TAA history: bind "
                "capture:TAAHistory where the capture has one)"},
        gbuffer::velocityInput("the hit texel's motion to last frame (none: the cameras)"),
    };
    io.outputs = {
        {.name = kReflection, .channels = {"R", "G", "B", "A"}, .kind = PortKind::Color,
         .doc = "premultiplied reflected radiance × fade, A = coverage (mean vignette of the rays)"},
        {.name = kHitMask, .channels = {"Y"}, .doc = "debug: fraction of rays that hit"},
        {.name = kHitDistance, .channels = {"Y"}, .doc = "debug: mean distance to the hits, scene units (0: none)"},
    };
    io.needsCamera = true;
    io.workUnit = "hzbSamples";
    io.temporal = mParams.temporal;
    return io;
}

void SSRPass::execute(PassContext& ctx) {
    const Image& depthImage = ctx.input(gbuffer::kDepth)->image();
    const int W = depthImage.width(), H = depthImage.height();
    Image& out = ctx.output(kReflection, {{W, H}}).image();
    Image* hitMask = ctx.isRequested(kHitMask) ? &ctx.output(kHitMask, {{W, H}}).image() : nullptr;
    Image* hitDistance = ctx.isRequested(kHitDistance) ? &ctx.output(kHitDistance, {{W, H}}).image() : nullptr;

    Frame f{};
    f.quality = effectiveQuality(mParams.quality, mParams.postProcessQuality, mParams.intensity);
    if (f.quality.level == 0) {
        ctx.addWork("skippedPixels", uint64_t(W) * H);
        return;  // the output stays 0: no reflection, no coverage
    }
    const FrameInfo& info = ctx.frame();
    const Texture& hzb = *ctx.input(kFurthestHzb);
    FP_CHECK(hzb.mipCount() >= 1 && hzb.mipCount() <= kMaxHzbMips,
             "furthestHzb has {} mips; SSR reads 1 to {}", hzb.mipCount(), kMaxHzbMips);
    bindScreenRayCamera(f.march, info.camera.current, W, H);
    f.march.hzb = hzbViewOf(hzb);
    f.march.steps = f.quality.steps;
    f.march.invSteps = 1.0f / float(f.march.steps);
    f.singleRay = f.march;
    f.singleRay.steps = std::min(f.quality.steps * f.quality.rays, kSingleRayMaxSteps);
    f.singleRay.invSteps = 1.0f / float(f.singleRay.steps);
    f.previous = info.camera.previous.value_or(info.camera.current);
    f.frameMod8 = ue::frameIndexMod8(info.number);
    f.maxRoughness = mParams.maxRoughness;
    f.intensityScale = std::clamp(mParams.intensity * 0.01f, 0.0f, 1.0f);
    f.depth = &depthImage.plane(0);
    f.normal = &ctx.input(gbuffer::kNormal)->image();
    f.roughness = &ctx.input(gbuffer::kRoughness)->image().plane(0);
    f.shadingModel = &ctx.input(gbuffer::kShadingModel)->image().plane(0);
    f.color = &ctx.input(kColor)->image();
    FP_CHECK(f.color->width() == W && f.color->height() == H,
             "the colour input is {}×{}, the frame {}×{}", f.color->width(), f.color->height(), W, H);
    if (const Texture* cd = ctx.input(gbuffer::kCustomData)) f.customData = &cd->image();
    f.velocity = velocityViewOf(ctx.input(kVelocity));
    const CameraView& cam = f.march.cam;

    std::array<std::atomic<uint64_t>, kCounterCount> totals{};
    forEachTile(W, H, [&](const Tile& t) {
        std::array<uint64_t, kCounterCount> counts{};
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const double d = f.depth->at(x, y);
                const float modelValue = f.shadingModel->at(x, y);
                if (!isLitSurface(d, modelValue)) {
                    ++counts[kSkipped];
                    continue;
                }
                float roughness = f.roughness->at(x, y);
                if (truncToInt(modelValue, 0, 255) == kClearCoat && f.customData) {
                    // §5.2, 4.27/5.0: the coat's roughness blended in by its amount.
                    const float coat = saturate(f.customData->plane(0).at(x, y));
                    roughness += (saturate(f.customData->plane(1).at(x, y)) - roughness) * coat;
                }
                const float fade = roughnessFade(roughness, f.maxRoughness, f.quality.level);
                if (fade <= 0.0f) {  // Unreal's stencil pre-pass: no rays, output 0
                    ++counts[kRough];
                    continue;
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
                const Vec3d pd = cam.translatedFromPixel(x, y, d);
                const Vec3f V = normalize(-Vec3f{float(pd.x), float(pd.y), float(pd.z)});
                const Vec3f N = normalize(gbuffer::worldNormalAt(*f.normal, x, y));
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
                        const Vec3f Hn = sampleGgxVisibleNormal(N, V, alpha, e1, e2);
                        L = reflect(V, Hn);
                    } else {
                        L = reflect(V, N);
                    }
                    const Vec3f Lview{float(dot(Vec3d(L), cam.right)), float(dot(Vec3d(L), cam.up)),
                                      float(dot(Vec3d(L), cam.forward))};
                    RaySteps raySteps;
                    if (!screenRaySteps(g, o, Lview, kToleranceScale, raySteps)) continue;
                    float level, time = 0.0f;
                    if (marchHzb(g.hzb, raySteps, steps, levelStep, level, hzbSamples, &time) < 0) continue;
                    const RaySample s = shadeHit(f, raySteps, time);
                    if (!s.hit) continue;
                    ++hits;
                    distanceSum += float(length(s.offset - pd));
                    // §5.4: Karis-weight each ray when there are several.
                    const float karis = rays > 1 ? 1.0f / (1.0f + ue::luma(s.rgb[0], s.rgb[1], s.rgb[2])) : 1.0f;
                    for (int c = 0; c < 3; ++c) sum[c] += s.rgb[c] * karis;
                    coverage += s.alpha;
                }
                counts[kRays] += uint64_t(rays);
                counts[kHzbSamples] += hzbSamples;
                const float inv = 1.0f / float(rays);
                float mean[3] = {sum[0] * inv, sum[1] * inv, sum[2] * inv};
                if (rays > 1) {
                    const float inverseKaris = 1.0f / (1.0f - ue::luma(mean[0], mean[1], mean[2]));
                    for (float& m : mean) m *= inverseKaris;
                }
                const float scale = fade * f.intensityScale;
                for (int c = 0; c < 3; ++c) out.plane(c).at(x, y) = mean[c] * scale;
                out.plane(3).at(x, y) = coverage * inv * scale;
                if (hitMask) hitMask->plane(0).at(x, y) = float(hits) * inv;
                if (hitDistance && hits > 0) hitDistance->plane(0).at(x, y) = distanceSum / float(hits);
            }
        for (int i = 0; i < kCounterCount; ++i) totals[size_t(i)] += counts[size_t(i)];
    });
    if (mParams.temporal) {
        const PassHistory* history = ctx.history();
        if (history && history->state.image().width() == W && history->state.image().height() == H)
            ctx.addWork("historyPixels", smoothTemporally(out, history->state.image(), history->camera, cam,
                                                          *f.depth, f.velocity));
        ctx.keepHistory(Texture(copyOf(out)));
    }
    ctx.addWork("pixels", totals[kTraced]);
    ctx.addWork("skippedPixels", totals[kSkipped]);
    ctx.addWork("roughPixels", totals[kRough]);
    ctx.addWork("rays", totals[kRays]);
    ctx.addWork("hzbSamples", totals[kHzbSamples]);
}

}  // namespace fp
