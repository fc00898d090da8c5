#pragma once
// SSGI's per-pixel work (algorithms §4.3–4.8), written once for both backends: SSGIPass::execute
// calls ssgiPixel from its tile loop, SSGIPass.cu from one CUDA thread per traced pixel. Everything
// a pixel reads is in SSGIFrame, plain views passed by value.
#include "screenspace/GBuffer.h"
#include "screenspace/HzbMarch.h"
#include "screenspace/Surface.h"
#include "screenspace/TraceResolution.h"
#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "framework/Pass.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "foundation/UnrealRandom.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace fp::ssgi {

// Ports (besides the GBuffer's, gbuffer::k*).
inline constexpr const char* kFurthestHzb = "furthestHzb";
inline constexpr const char* kReducedColor = "reducedColor";
inline constexpr const char* kDiffuse = "diffuse";
inline constexpr const char* kAo = "ao";
inline constexpr const char* kHitMask = "hitMask";
inline constexpr const char* kHitDistance = "hitDistance";

constexpr float kStepOffsetBias = -0.9f;  // algorithms §4.6: IGN − 0.9 for SSGI (−0.5 for SSR)
constexpr float kToleranceScale = 2.0f;   // algorithms §4.5: k = 2 for SSGI (4 for SSR)
constexpr int kReducedMips = 5;           // prev_color_reduction's chain (algorithms §3.1)

/// What every ray of the frame shares: the screen-space march's frame, and SSGI's own.
struct TraceSetup : ScreenRayFrame {
    PlaneView reduced[kReducedMips][3];  //!< last frame's colour, R G B per mip
    int rays;
    uint32_t frameMod8;
    float levelStep;
    // Largest valid reduced-colour texel per mip (algorithms §3.4 ReducedColorUVMax).
    int reducedMaxX[kReducedMips], reducedMaxY[kReducedMips];
};

/// Everything one frame's pixels read and write. Absent outputs have null data.
struct Frame {
    TraceSetup setup;
    PlaneView depth, normal[3], shadingModel;
    PlaneSpan diffuse[3], ao, hitMask, hitDistance;
    int width, height;  //!< full resolution
    int toFull;         //!< 2 when tracing at half resolution
    float colorScale;   //!< indirectLightingColorScale
};

/// Work counted per pixel, in this order.
enum Counter { kTraced, kSkipped, kRays, kHzbSamples, kCounterCount };


// The view-space normal goes through 8 bits per axis in Unreal's LDS (algorithms §4.3).
FP_HD inline Vec3f quantiseNormal(const Vec3f& n) {
    auto q = [](float v) { return std::round((v * 0.5f + 0.5f) * 255.0f) / 255.0f * 2.0f - 1.0f; };
    return normalize(Vec3f{q(n.x), q(n.y), q(n.z)});
}

/// Ray `index` of `count` of trace pixel (x, y) on frame index `frameMod8`, in view space around
/// unit view-space normal `n` (algorithms §4.4: PCG seed, Hammersley, concentric-disk cosine).
FP_HD inline Vec3f rayDirection(const Vec3f& n, int x, int y, uint32_t frameMod8, int index,
                                int count) {
    const ue::Rand3 seed = ue::rand3DPCG16(x, y, int32_t(frameMod8));
    float e1, e2, dx, dy;
    ue::hammersley16(uint32_t(index), uint32_t(count), seed.x, seed.y, e1, e2);
    ue::concentricDisk(e1, e2, dx, dy);
    const float dz = std::sqrt(std::max(0.0f, 1.0f - dx * dx - dy * dy));
    Vec3f t, b;
    orthonormalBasis(n, t, b);
    return t * dx + b * dy + n * dz;
}

// The per-pixel start of every ray (algorithms §4.3–4.5): the shared origin and the quantised
// view-space normal the rays are drawn around.
struct PixelStart : ScreenRayOrigin {
    Vec3f nView;
};

FP_HD inline PixelStart
pixelStart(const Frame& f, int x, int y, int px, int py, double d) {
    const TraceSetup& s = f.setup;
    const CameraView& cam = s.cam;
    const Vec3d nw(Vec3f{f.normal[0].at(px, py), f.normal[1].at(px, py), f.normal[2].at(px, py)});
    PixelStart p;
    static_cast<ScreenRayOrigin&>(p) = screenRayOrigin(
        s, px, py, d,
        ue::interleavedGradientNoise(float(x) + 0.5f, float(y) + 0.5f, s.frameMod8) + kStepOffsetBias);
    p.nView = quantiseNormal(
        Vec3f{float(dot(nw, cam.right)), float(dot(nw, cam.up)), float(dot(nw, cam.forward))});
    return p;
}

// algorithms §4.5 with SSGI's tolerance.
FP_HD inline bool raySteps(const TraceSetup& s, const PixelStart& p, const Vec3f& L, RaySteps& r) {
    return screenRaySteps(s, p, L, kToleranceScale, r);
}

// Last frame's colour where a ray hit, at the level it reached (point, nearest mip; §4.7).
FP_HD inline void hitColor(const TraceSetup& s, const RayPoint& hit, float level, float c[3]) {
    const int mip = nearestMip(level, kReducedMips);
    const float scale = inversePowerOfTwo(mip);
    const int rx = floorToInt(hit.hx * scale, 0, s.reducedMaxX[mip]);
    const int ry = floorToInt(hit.hy * scale, 0, s.reducedMaxY[mip]);
    c[0] = s.reduced[mip][0].at(rx, ry);
    c[1] = s.reduced[mip][1].at(rx, ry);
    c[2] = s.reduced[mip][2].at(rx, ry);
}

// View-space distance from the pixel to a hit (debug output); false for a hit on the sky.
FP_HD inline bool viewDistanceToHit(const TraceSetup& s,
                                    const PixelStart& p,
                                    const RayPoint& hit,
                                    double& distance) {
    const double hd = s.cam.depthFromDeviceZ(hit.z);
    if (!std::isfinite(hd))
        return false;
    const double d = p.depth;
    const double hsx = hit.hx / s.halfW * 2.0 - 1.0;
    const double hsy = 1.0 - hit.hy / s.halfH * 2.0;
    const Vec3d a{(p.sx - s.cx) * d / s.fx, (p.sy - s.cy) * d / s.fy, d};
    const Vec3d b{(hsx - s.cx) * hd / s.fx, (hsy - s.cy) * hd / s.fy, hd};
    distance = std::sqrt(dot(b - a, b - a));
    return true;
}

// What one ray brought back.
struct RayTrace {
    bool hit = false;
    bool measured = false;  // a hit whose distance was measured (not the sky)
    float weighted[3] = {0, 0, 0};  // last frame's colour at the hit, Karis-weighted (§4.7)
    double distance = 0;
};

// algorithms §4.7: the colour `c` a ray brings from `hit` (last frame's colour there; the hybrid
// may add to it), Karis-weighted, and (when wanted) the distance to the hit.
FP_HD inline RayTrace weighHit(const TraceSetup& s,
                               const PixelStart& p,
                               const RayPoint& hit,
                               const float c[3],
                               bool wantDistance) {
    RayTrace t;
    const float karis = 1.0f / (1.0f + ue::luma(c[0], c[1], c[2]));
    for (int ch = 0; ch < 3; ++ch)
        t.weighted[ch] = c[ch] * karis;
    t.hit = true;
    t.measured = wantDistance && viewDistanceToHit(s, p, hit, t.distance);
    return t;
}

// algorithms §4.7 for a ray that hit at sample `hitSample` having reached mip level `level`:
// last frame's colour there, Karis-weighted, and (when wanted) the distance to the hit.
FP_HD inline RayTrace shadeHit(const TraceSetup& s,
                               const PixelStart& p,
                               const RaySteps& steps,
                               int hitSample,
                               float level,
                               bool wantDistance) {
    const RayPoint hit = rayPointAt(steps, float(hitSample));
    float c[3];
    hitColor(s, hit, level, c);
    return weighHit(s, p, hit, c, wantDistance);
}

/// What SSGI's rays do beyond the screen: in Unreal's SSGI, nothing — a ray its march cannot
/// finish brings no light, and an on-screen hit brings last frame's colour alone. framepass's
/// hybrid passes a callable of the same shape (passes/hybrid/HybridKernel.h) that traces such a
/// ray through the scene and may continue an on-screen hit's path; its per-pixel state is
/// `Pixel`, made once a pixel by begin().
struct NoFallback {
    struct Pixel {};
    FP_HD Pixel begin(const Frame&, int, int) const { return {}; }
    /// Whether on-screen hits go through onScreenHit (else their colour is last frame's alone).
    FP_HD bool continuesHits() const { return false; }
    /// Adds to `c` (last frame's colour at an on-screen hit) what the path after it brings.
    FP_HD void onScreenHit(Pixel&, const RayPoint&, float[3]) const {}
    /// What ray `L` (view space) of pixel (x, y), which the screen could not finish, brings.
    FP_HD RayTrace miss(Pixel&, int, int, const Vec3f&) const { return {}; }
    /// After the pixel's last ray (the fallback's own counts).
    FP_HD void end(Pixel&) const {}
};

// algorithms §4.4–4.7 for ray `r` of a traced pixel, one ray at a time: the scalar reference that
// the CPU's SIMD lanes (SSGILanes.cpp) reproduce bit for bit, and the GPU's per-thread loop;
// with a fallback (the hybrid's), what the screen cannot finish is the fallback's.
template <class Fallback = NoFallback>
FP_HD inline RayTrace traceRay(const TraceSetup& s,
                               const PixelStart& p,
                               int x,
                               int y,
                               int r,
                               bool wantDistance,
                               unsigned& hzbSamples,
                               const Fallback& fallback = {},
                               typename Fallback::Pixel* pixel = nullptr) {
    const Vec3f L = rayDirection(p.nView, x, y, s.frameMod8, r, s.rays);
    RaySteps steps;
    if (raySteps(s, p, L, steps)) {
        float level;
        const int hitSample = marchHzb(s.hzb, steps, s.steps, s.levelStep, level, hzbSamples);
        if (hitSample >= 0) {
            if (!fallback.continuesHits())
                return shadeHit(s, p, steps, hitSample, level, wantDistance);
            // Last frame's colour at the hit, plus what the fallback's path after it brings.
            const RayPoint hit = rayPointAt(steps, float(hitSample));
            float c[3];
            hitColor(s, hit, level, c);
            fallback.onScreenHit(*pixel, hit, c);
            return weighHit(s, p, hit, c, wantDistance);
        }
    }
    return pixel ? fallback.miss(*pixel, x, y, L) : RayTrace{};
}

// What one pixel's rays gathered, summed in ray order.
struct PixelTrace {
    float sum[3] = {0, 0, 0};
    int hits = 0;
    int measuredHits = 0;
    double distanceSum = 0;

    FP_HD void add(const RayTrace& t) {
        if (!t.hit)
            return;
        for (int ch = 0; ch < 3; ++ch)
            sum[ch] += t.weighted[ch];
        ++hits;
        if (t.measured) {
            distanceSum += t.distance;
            ++measuredHits;
        }
    }
};

/// algorithms §4.8: the mean of the rays with the Karis weighting undone, written out.
FP_HD inline void finishPixel(const Frame& f, int x, int y, const PixelTrace& t) {
    const float invRays = 1.0f / float(f.setup.rays);
    const float mean[3] = {t.sum[0] * invRays, t.sum[1] * invRays, t.sum[2] * invRays};
    const float inverseKaris = 1.0f / (1.0f - ue::luma(mean[0], mean[1], mean[2]));
    for (int ch = 0; ch < 3; ++ch)
        f.diffuse[ch].at(x, y) = mean[ch] * inverseKaris * f.colorScale;
    const float hitFraction = float(t.hits) * invRays;
    f.ao.at(x, y) = 1.0f - hitFraction;
    if (f.hitMask)
        f.hitMask.at(x, y) = hitFraction;
    if (f.hitDistance && t.measuredHits > 0)
        f.hitDistance.at(x, y) = float(t.distanceSum / t.measuredHits);
}

/// The start of trace pixel (x, y): false for a pixel SSGI skips (unlit or sky), whose outputs
/// are then written and which is counted as skipped; otherwise counted as traced.
FP_HD inline bool beginPixel(const Frame& f, int x, int y, unsigned long long* counts,
                             PixelStart& start) {
    const PixelCoord p = fullResPixel(x, y, f.toFull, f.width, f.height);
    const double d = f.depth.at(p.x, p.y);
    if (!isLitSurface(d, f.shadingModel.at(p.x, p.y))) {
        f.ao.at(x, y) = 1.0f;  // diffuse, hit mask, distance stay 0
        ++counts[kSkipped];
        return false;
    }
    ++counts[kTraced];
    start = pixelStart(f, x, y, p.x, p.y, d);
    return true;
}

/// One trace pixel (x, y) of the frame: skipped (unlit or sky) or traced ray after ray (what the
/// screen cannot finish the fallback's), its outputs written and its work added to `counts`
/// (indexed by Counter).
template <class Fallback = NoFallback>
FP_HD inline void ssgiPixel(const Frame& f, int x, int y, unsigned long long* counts,
                            const Fallback& fallback = {}) {
    PixelStart start;
    if (!beginPixel(f, x, y, counts, start))
        return;
    PixelTrace t;
    unsigned hzbSamples = 0;  // a pixel's rays × steps fits; one 32-bit register on the GPU
    typename Fallback::Pixel pixel = fallback.begin(f, x, y);
    for (int r = 0; r < f.setup.rays; ++r)
        t.add(traceRay(f.setup, start, x, y, r, bool(f.hitDistance), hzbSamples, fallback, &pixel));
    fallback.end(pixel);
    counts[kRays] += (unsigned long long)f.setup.rays;
    counts[kHzbSamples] += hzbSamples;
    finishPixel(f, x, y, t);
}

/// The frame as ssgiPixel reads it, bound through HostPorts or DevicePorts (PassPorts.h).
/// Outputs are allocated here; hitMask and hitDistance only when something reads them.
template <class Ports>
Frame bindFrame(const Ports& ports,
                const FrameInfo& frame,
                int rays,
                int steps,
                bool halfRes,
                float colorScale) {
    const auto& depth = *ports.input(gbuffer::kDepth);
    const auto& normal = *ports.input(gbuffer::kNormal);
    const auto& shadingModel = *ports.input(gbuffer::kShadingModel);
    const auto& hzb = *ports.input(kFurthestHzb);
    const auto& reduced = *ports.input(kReducedColor);
    FP_CHECK(reduced.mipCount() >= kReducedMips, "reducedColor has {} mips; SSGI needs {}",
             reduced.mipCount(), kReducedMips);
    FP_CHECK(hzb.mipCount() >= 1 && hzb.mipCount() <= kMaxHzbMips,
             "furthestHzb has {} mips; SSGI reads 1 to {}", hzb.mipCount(), kMaxHzbMips);
    Frame f{};
    f.width = depth.image().width();
    f.height = depth.image().height();
    f.toFull = halfRes ? 2 : 1;
    f.colorScale = colorScale;
    const std::vector<Extent> trace = {fp::traceExtent({f.width, f.height}, halfRes)};

    TraceSetup& s = f.setup;
    bindScreenRayCamera(s, frame.camera.current, f.width, f.height);
    s.hzb = hzbViewOf(hzb);
    s.rays = rays;
    s.steps = steps;
    s.frameMod8 = ue::frameIndexMod8(frame.number);
    s.invSteps = 1.0f / float(steps);
    s.levelStep = 8.0f * s.invSteps;  // algorithms §4.6: (8/N)·Roughness, Roughness = 1
    for (int m = 0; m < kReducedMips; ++m) {
        for (int c = 0; c < 3; ++c)
            s.reduced[m][c] = viewOf(reduced.mip(m).plane(c));
        s.reducedMaxX[m] = std::max(0, int(std::ceil(s.halfW / float(1 << m))) - 1);
        s.reducedMaxY[m] = std::max(0, int(std::ceil(s.halfH / float(1 << m))) - 1);
    }

    f.depth = viewOf(depth.image().plane(0));
    f.shadingModel = viewOf(shadingModel.image().plane(0));
    auto& diffuse = ports.output(kDiffuse, trace);
    for (int c = 0; c < 3; ++c) {
        f.normal[c] = viewOf(normal.image().plane(c));
        f.diffuse[c] = spanOf(diffuse.image().plane(c));
    }
    f.ao = spanOf(ports.overwrite(kAo, trace).image().plane(0));
    if (auto* hitMask = ports.outputIfRequested(kHitMask, trace))
        f.hitMask = spanOf(hitMask->image().plane(0));
    if (auto* hitDistance = ports.outputIfRequested(kHitDistance, trace))
        f.hitDistance = spanOf(hitDistance->image().plane(0));
    return f;
}

/// The pass's work counts, as the report shows them.
inline void reportWork(PassContext& ctx, const std::array<uint64_t, kCounterCount>& counts) {
    ctx.addWork("pixels", counts[kTraced]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
    ctx.addWork("rays", counts[kRays]);
    ctx.addWork("hzbSamples", counts[kHzbSamples]);
}

/// The whole pass one ray at a time (PerPixel.h): one ssgiPixel per trace pixel. The GPU runs
/// this; the CPU too when `ssgi.lanes` is off, and the hybrid with its fallback.
template <class Ports, class Pixels, class Fallback = NoFallback>
std::array<uint64_t, kCounterCount> run(PassContext& ctx,
         const Ports& ports,
         const Pixels& pixels,
         int rays,
         int steps,
         bool halfRes,
         float colorScale,
         const Fallback& fallback = {},
         const char* what = "ssgi") {
    const Frame f = bindFrame(ports, ctx.frame(), rays, steps, halfRes, colorScale);
    const auto counts = pixels.template forEach<kCounterCount>(
        f.ao.width, f.ao.height,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& c) {
            ssgiPixel(f, x, y, c.value, fallback);
        },
        what);
    reportWork(ctx, counts);
    return counts;
}

}  // namespace fp::ssgi
