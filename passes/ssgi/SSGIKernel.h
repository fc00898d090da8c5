#pragma once
// SSGI's per-pixel work (algorithms §4.3–4.8), written once for every backend: ssgiPixel<float>
// is the scalar reference (SSGIPass::execute's tile loop with `lanes` off, SSGIPass.cu's CUDA
// thread per traced pixel, the hybrid), and SSGILanes.cpp's builds (SSE4, AVX2, AVX-512) run
// ssgiPixel<LaneFloat<N>>, a pixel's rays N at a time, the same operations in every lane.
// Everything a pixel reads is in Frame, plain views passed by value.
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

/// What every ray of a trace pixel shares in its direction (algorithms §4.4): the PCG seed of the
/// pixel and frame index, and the tangent frame around the unit view-space normal.
struct RayBasis {
    ue::Rand3 seed;
    Vec3f n, t, b;
};

FP_HD inline RayBasis rayBasis(const Vec3f& n, int x, int y, uint32_t frameMod8) {
    RayBasis r;
    r.seed = ue::rand3DPCG16(x, y, int32_t(frameMod8));
    r.n = n;
    orthonormalBasis(n, r.t, r.b);
    return r;
}

/// Ray `index` of `count` in view space (algorithms §4.4: Hammersley scrambled by the pixel's
/// seed, concentric-disk cosine around its normal). T: float, or float lanes with each lane's ray
/// index in `index`.
template <class T>
FP_HD inline Vec3T<T> rayDirection(const RayBasis& basis, UIntOf<T> index, int count) {
    T e1, e2, dx, dy;
    ue::hammersley16(index, uint32_t(count), basis.seed.x, basis.seed.y, e1, e2);
    ue::concentricDisk(e1, e2, dx, dy);
    const T dz = sqrtOf(maxLike(T(0.0f), 1.0f - dx * dx - dy * dy));
    return Vec3T<T>(basis.t) * dx + Vec3T<T>(basis.b) * dy + Vec3T<T>(basis.n) * dz;
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
template <class T>
FP_HD inline MaskOf<T> raySteps(const TraceSetup& s, const PixelStart& p, const Vec3T<T>& L,
                                RayStepsT<T>& r) {
    return screenRaySteps(s, p, L, kToleranceScale, r);
}

// Last frame's colour where a ray hit, at the level it reached (point, nearest mip; §4.7); 0
// where `where` does not hold. Each lane reads the mip of its own level: one read of every lane
// per mip some lane reached (a gather with lanes; at float, the one mip of the ray).
template <class T>
FP_HD inline void hitColor(const TraceSetup& s, const RayPointT<T>& hit, T level, MaskOf<T> where, T c[3]) {
    const IntOf<T> mip = nearestMipOf(level, kReducedMips);
    for (int ch = 0; ch < 3; ++ch)
        c[ch] = T(0.0f);
    for (int m = 0; m < kReducedMips; ++m) {
        const MaskOf<T> onMip = where & (mip == m);
        if (!anyLane(onMip))
            continue;
        const float scale = inversePowerOfTwo(m);
        const IntOf<T> rx = floorToIntOf(hit.hx * scale, 0, s.reducedMaxX[m]);
        const IntOf<T> ry = floorToIntOf(hit.hy * scale, 0, s.reducedMaxY[m]);
        for (int ch = 0; ch < 3; ++ch)
            c[ch] = ifThenElse(onMip, gatherAt(s.reduced[m][ch], rx, ry), c[ch]);
    }
}

// §4.7's Karis weight of colour c: c / (1 + luma(c)).
template <class T>
FP_HD inline void karisWeighted(const T c[3], T weighted[3]) {
    const T karis = 1.0f / (1.0f + ue::luma(c[0], c[1], c[2]));
    for (int ch = 0; ch < 3; ++ch)
        weighted[ch] = c[ch] * karis;
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
    karisWeighted(c, t.weighted);
    t.hit = true;
    t.measured = wantDistance && viewDistanceToHit(s, p, hit, t.distance);
    return t;
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
    /// Adds an on-screen hit's light `r` to the pixel's sum `trace` (a fallback may note it).
    template <class Trace>
    FP_HD void addHit(Pixel&, Trace& trace, const RayTrace& r) const {
        trace.add(r);
    }
    /// After the pixel's last ray (the fallback's own counts).
    FP_HD void end(Pixel&) const {}
};

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

/// algorithms §4.4–4.7 for the rays `first`, `first` + 1, … of a traced pixel, kLanesOf<T> at a
/// time (T: float, the scalar reference and the GPU's per-thread loop; float lanes on the CPU, a
/// ray a lane, the same operations in every lane), their light added to `trace` in ray order.
/// With a fallback (the hybrid's), what the screen cannot finish is the fallback's.
template <class T, class Fallback>
FP_HD inline void traceRays(const TraceSetup& s,
                            const PixelStart& p,
                            const RayBasis& basis,
                            int x,
                            int y,
                            int first,
                            bool wantDistance,
                            unsigned& hzbSamples,
                            PixelTrace& trace,
                            const Fallback& fallback,
                            typename Fallback::Pixel& pixel) {
    using M = MaskOf<T>;
    const UIntOf<T> index = LaneTypes<T>::indices() + uint32_t(first);
    const M inUse = index < uint32_t(s.rays);
    const Vec3T<T> L = rayDirection<T>(basis, index, s.rays);
    RayStepsT<T> steps{};  // (set where a lane is traced; the march reads no other lane)
    const M traced = inUse & raySteps(s, p, L, steps);
    T level;
    const T hitSample = marchHzb(s.hzb, steps, s.steps, s.levelStep, level, hzbSamples, (T*)nullptr, traced);
    const M hits = traced & (hitSample >= 0.0f);
    const int count = s.rays - first < kLanesOf<T> ? s.rays - first : kLanesOf<T>;
    if (!anyLane(hits)) {
        for (int i = 0; i < count; ++i)
            trace.add(fallback.miss(pixel, x, y, laneOf(L, i)));
        return;
    }
    const RayPointT<T> hit = rayPointAt(steps, hitSample);
    if (!wantDistance && !fallback.continuesHits()) {
        // The hits' colours and Karis weights, every lane at once.
        T c[3], weighted[3];
        hitColor(s, hit, level, hits, c);
        karisWeighted(c, weighted);
        for (int i = 0; i < count; ++i) {
            if (!laneOf(hits, i)) {
                trace.add(fallback.miss(pixel, x, y, laneOf(L, i)));
                continue;
            }
            RayTrace t;
            t.hit = true;
            for (int ch = 0; ch < 3; ++ch)
                t.weighted[ch] = laneOf(weighted[ch], i);
            fallback.addHit(pixel, trace, t);
        }
        return;
    }
    // One hit at a time: the debug distance, or a fallback that continues the hit's path.
    for (int i = 0; i < count; ++i) {
        if (!laneOf(hits, i)) {
            trace.add(fallback.miss(pixel, x, y, laneOf(L, i)));
            continue;
        }
        const RayPoint h{laneOf(hit.hx, i), laneOf(hit.hy, i), laneOf(hit.z, i)};
        float c[3];
        hitColor(s, h, laneOf(level, i), true, c);
        if (fallback.continuesHits())
            fallback.onScreenHit(pixel, h, c);  // adds what the path after the hit brings
        fallback.addHit(pixel, trace, weighHit(s, p, h, c, wantDistance));
    }
}

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

/// One trace pixel (x, y) of the frame: skipped (unlit or sky) or traced, kLanesOf<T> rays at a
/// time (what the screen cannot finish the fallback's), its outputs written and its work added to
/// `counts` (indexed by Counter). T = float is the scalar reference (the GPU's thread, the CPU
/// with `ssgi.lanes` off, the hybrid); SSGILanes.cpp runs it with float lanes, the same bits.
template <class T = float, class Fallback = NoFallback>
FP_HD inline void ssgiPixel(const Frame& f, int x, int y, unsigned long long* counts,
                            const Fallback& fallback = {}) {
    PixelStart start;
    if (!beginPixel(f, x, y, counts, start))
        return;
    const RayBasis basis = rayBasis(start.nView, x, y, f.setup.frameMod8);
    PixelTrace t;
    unsigned hzbSamples = 0;  // a pixel's rays × steps fits; one 32-bit register on the GPU
    typename Fallback::Pixel pixel = fallback.begin(f, x, y);
    for (int first = 0; first < f.setup.rays; first += kLanesOf<T>)
        traceRays<T>(f.setup, start, basis, x, y, first, bool(f.hitDistance), hzbSamples, t, fallback, pixel);
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
