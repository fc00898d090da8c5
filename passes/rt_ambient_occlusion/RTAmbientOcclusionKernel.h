#pragma once
// rt_ambient_occlusion's per-pixel work (algorithms §12.1, Unreal 4.27's
// RayTracingAmbientOcclusionRGS): a pixel's set-up — its position from depth, its geometric
// normal from the neighbours' depths, how far its shading normal leans from it — each sample's
// cosine-weighted ray about the geometric normal with its weight, and the resolve. Written as
// FP_HD functions over plane views: the CPU's Embree path batches their rays into packets, and
// run() traces them one pixel at a time through framepass's BVH (Bvh.h), on the CPU (traversal
// "bvh") and on the GPU (RTAmbientOcclusionPass.cu), the same code.
#include "foundation/Bvh.h"
#include "foundation/Camera.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Random.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "framework/Pass.h"
#include "screenspace/GBuffer.h"
#include "shading/RayOriginBias.h"

#include <cstdint>

namespace fp::rtao {

inline constexpr const char* kAo = "ao";
inline constexpr const char* kHitDistance = "hitDistance";

/// Unreal's hit distance where no ray hit anything: 10000 (its units, cm), in scene units here
/// scaled by the scene's centimetre. Sky and unlit pixels write −2.
inline constexpr float kNoHitCm = 10000.0f;
inline constexpr float kSkippedHitDistance = -2.0f;

/// A clamped cosine lobe as a spherical Gaussian μ·e^{λ(v·axis − 1)}: Unreal's
/// ClampedCosine_ToSphericalGaussian sharpness (inferred, algorithms §12.1).
inline constexpr double kCosineLobeSharpness = 2.133;

/// What every pixel of a frame shares.
struct FrameSetup {
    CameraView camera;
    Vec3d eyeOffset;        // the eye relative to the RayScene origin
    int spp;                // samples per pixel
    float radius;           // scene units: the rays' tfar
    float intensity;        // 0–1: a blocked ray counts 1 − intensity
    float maxBias, minBias; // scene units
    float noHitDistance;    // kNoHitCm in scene units
    uint32_t rngKey;        // Rng::frameKey(frame, seed)
};

/// What stays the same for every sample of one pixel.
struct Pixel {
    Vec3f p;              // position relative to the RayScene origin
    Vec3f shading;        // the GBuffer normal, unit
    Vec3f geometric;      // from the neighbours' depths, facing the camera
    Vec3f tangent, bitangent;  // orthonormalBasis(geometric): the rays' frame
    Vec3f toEye;          // unit
    float eyeDistance;
    float shadingDotGeometric;  // how much of the shading lobe the geometric hemisphere holds
    uint32_t rng;
};

/// sinh(x)/x = Σ x^{2k}/(2k+1)! for 0 ≤ x ≤ 2λ (|a + b| ≤ 2), by Horner in x² over 16 terms (the
/// last is below 10⁻¹⁵ of the sum at x = 2λ): no division and no exponential, so a pixel's lobe
/// overlap costs a few multiplications.
FP_HD constexpr double sinhOverX(double x) {
    constexpr double kInverseOddFactorial[16] = {
        1.0,
        1.0 / 6.0,
        1.0 / 120.0,
        1.0 / 5040.0,
        1.0 / 362880.0,
        1.0 / 39916800.0,
        1.0 / 6227020800.0,
        1.0 / 1307674368000.0,
        1.0 / 355687428096000.0,
        1.0 / 121645100408832000.0,
        1.0 / 51090942171709440000.0,
        1.0 / 25852016738884976640000.0,
        1.0 / 15511210043330985984000000.0,
        1.0 / 10888869450418352160768000000.0,
        1.0 / 8841761993739701954543616000000.0,
        1.0 / 8222838654177922817725562880000000.0,
    };
    const double y = x * x;
    double sum = 0.0;
    for (int k = 15; k >= 0; --k) sum = sum * y + kInverseOddFactorial[k];
    return sum;
}

/// A cosine lobe's overlap with itself, sinh(2λ)/(2λ): the ratio's denominator, once.
inline constexpr double kSelfOverlap = sinhOverX(2.0 * kCosineLobeSharpness);

/// The overlap of two clamped cosine lobes about unit a and b as spherical Gaussians, over a
/// lobe's overlap with itself: ∫G_a·G_b = 4π·e^{−2λ}·sinh(d)/d with d = λ|a + b|, so the ratio is
/// (sinh(d)/d)·(2λ/sinh(2λ)), 1 for a = b, saturated.
FP_HD inline float lobeOverlap(const Vec3f& a, const Vec3f& b) {
    const Vec3f s = a + b;
    const double d = kCosineLobeSharpness * std::sqrt(double(dot(s, s)));
    const double ratio = sinhOverX(d) / kSelfOverlap;
    return float(ratio > 1.0 ? 1.0 : ratio);
}

/// The surface normal the depth buffer gives at (x, y) (algorithms §12.1): of the vectors to the
/// left and right neighbours the shorter, the same up and down, crossed and turned towards the
/// camera. The shading normal where a side has no surface on either hand (the screen's edge, sky)
/// or the vectors are parallel, and for two-sided foliage (thin: its faces bound nothing).
FP_HD FP_HOT_INLINE Vec3f geometricNormal(const FrameSetup& s, const PlaneView& depth, int x, int y,
                                   const Vec3d& centre, const Vec3f& shading, int model,
                                   const Vec3f& toEye) {
    if (model == kTwoSidedFoliage) return shading;
    auto neighbour = [&](int nx, int ny, Vec3d& q) {
        if (nx < 0 || ny < 0 || nx >= depth.width || ny >= depth.height) return false;
        const double d = depth.at(nx, ny);
        if (!(d > 0.0) || std::isinf(d)) return false;
        q = s.camera.translatedFromPixel(nx, ny, d);
        return true;
    };
    // The shorter of the two one-sided differences along an axis (either, where only one exists).
    auto along = [&](int dx, int dy, Vec3d& v) {
        Vec3d after, before;
        const bool a = neighbour(x + dx, y + dy, after), b = neighbour(x - dx, y - dy, before);
        if (!a && !b) return false;
        const Vec3d forward = after - centre, backward = centre - before;
        v = !b ? forward : (!a ? backward : (dot(forward, forward) < dot(backward, backward) ? forward : backward));
        return true;
    };
    Vec3d h, v;
    if (!along(1, 0, h) || !along(0, 1, v)) return shading;
    const Vec3d n = cross(h, v);
    const double len = length(n);
    if (!(len > 0.0)) return shading;
    Vec3f g(n / len);
    return dot(g, toEye) < 0.0f ? -g : g;
}

/// Pixel (x, y)'s set-up; false for sky and unlit pixels (they trace nothing).
FP_HD FP_HOT_INLINE bool setupPixel(const FrameSetup& s, const PlaneView& depth, const PlaneView& model,
                             const PlaneView (&normal)[3], int x, int y, Pixel& px) {
    const double d = depth.at(x, y);
    const float m = model.at(x, y);
    if (!isLitSurface(d, m)) return false;
    const Vec3d offset = s.camera.translatedFromPixel(x, y, d);
    px.p = Vec3f(s.eyeOffset + offset);
    const double eyeDistance = length(offset);
    px.eyeDistance = float(eyeDistance);
    px.toEye = Vec3f(-offset / eyeDistance);
    px.shading = Vec3f{normal[0].at(x, y), normal[1].at(x, y), normal[2].at(x, y)};
    px.geometric = geometricNormal(s, depth, x, y, offset, px.shading, truncToInt(m, 0, 255), px.toEye);
    px.shadingDotGeometric = lobeOverlap(px.shading, px.geometric);
    orthonormalBasis(px.geometric, px.tangent, px.bitangent);
    px.rng = Rng::fromKey(s.rngKey, x, y).state();
    return true;
}

/// One AO ray and its weight: cosine-distributed about the geometric normal (pdf ∝ cosθ there),
/// weighted by max(N_shading·dir, 0.05) / max(pdf, 0.05) so a shading normal that leans away
/// counts its own cosine (on a flat surface every weight is 1).
struct AoRay {
    Vec3f org, dir;
    float weight;
};
FP_HD FP_HOT_INLINE AoRay sampleRay(const FrameSetup& s, Pixel& px) {
    Rng rng = Rng::resume(px.rng);
    const float u = rng.nextFloat(), v = rng.nextFloat();
    px.rng = rng.state();
    // cosineHemisphere(px.geometric, u, v), its frame built once per pixel.
    float x, y;
    concentricDisk(u, v, x, y);
    const float z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
    const Vec3f dir = normalize(px.tangent * x + px.bitangent * y + px.geometric * z);
    const float NoL = dot(px.shading, dir);
    const float pdf = dot(px.geometric, dir);
    const float weight = (NoL > 0.05f ? NoL : 0.05f) / (pdf > 0.05f ? pdf : 0.05f);
    const Vec3f org = biasedRayOrigin(px.p, px.toEye, px.eyeDistance, px.shading, NoL,
                                      s.maxBias, s.minBias);
    return {org, dir, weight};
}

/// A pixel's sums over its samples.
struct Sums {
    float weighted = 0, weights = 0, closestHit = -1;
    FP_HD void add(const FrameSetup& s, float weight, bool blocked, float hitT) {
        weights += weight;
        weighted += weight * (blocked ? 1.0f - s.intensity : 1.0f);
        if (blocked && hitT >= 0.0f && (closestHit < 0.0f || hitT < closestHit)) closestHit = hitT;
    }
};

/// The pixel's outputs: the weighted visibility scaled by how much of its shading lobe the
/// geometric hemisphere holds; the closest hit (kNoHitCm where none hit, −1 with no weight).
struct Resolved {
    float ao, hitDistance;
};
FP_HD inline Resolved resolve(const FrameSetup& s, float shadingDotGeometric, const Sums& sums) {
    if (!(sums.weights > 0.0f)) return {shadingDotGeometric, -1.0f};
    return {shadingDotGeometric * (sums.weighted / sums.weights),
            sums.closestHit >= 0.0f ? sums.closestHit : s.noHitDistance};
}

/// The frame's planes and set-up, as the BVH path's pixels read them.
struct Frame {
    FrameSetup setup;
    BvhView bvh;
    bool wantDistance;  // the closest hit of each blocked ray (the hitDistance output is read)
    PlaneView depth, model, normal[3];
    PlaneSpan ao, hitDistance;
};

enum Counter { kRays, kPixels, kSkipped, kCounterCount };

/// Pixel (x, y) through the BVH: its set-up, each sample's ray (an any-hit query; where the hit
/// distance is read, a blocked ray's closest hit after it, as Embree's path asks), its resolve.
FP_HD inline void aoPixel(const Frame& f, int x, int y, WorkCounts<kCounterCount>& work) {
    Pixel px;
    if (f.setup.intensity <= 0.0f || !setupPixel(f.setup, f.depth, f.model, f.normal, x, y, px)) {
        f.ao.at(x, y) = 1.0f;
        f.hitDistance.at(x, y) = kSkippedHitDistance;
        ++work.value[kSkipped];
        return;
    }
    Sums sums;
    for (int k = 0; k < f.setup.spp; ++k) {
        const AoRay r = sampleRay(f.setup, px);
        const bool blocked =
            traceBvh(f.bvh, r.org, r.dir, 0.0f, f.setup.radius, BvhQuery{true, false, 0}) >= 0.0f;
        const float t = blocked && f.wantDistance
                            ? traceBvh(f.bvh, r.org, r.dir, 0.0f, f.setup.radius, BvhQuery{})
                            : -1.0f;
        sums.add(f.setup, r.weight, blocked, t);
    }
    const Resolved res = resolve(f.setup, px.shadingDotGeometric, sums);
    f.ao.at(x, y) = res.ao;
    f.hitDistance.at(x, y) = res.hitDistance;
    work.value[kRays] += uint32_t(f.setup.spp);
    ++work.value[kPixels];
}

/// The pass on the BVH path, one pixel at a time through `pixels`: CpuPixels for the CPU's
/// traversal "bvh", CudaPixels (a thread a pixel) on the GPU. At intensity 0 nothing is traced:
/// every pixel writes AO 1 and the skipped hit distance, as Unreal skips the pass.
template <class Ports, class Pixels>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const FrameSetup& setup) {
    const Extent size = ctx.frame().extent;
    Frame f{};
    f.setup = setup;
    f.bvh = ports.bvh();
    f.wantDistance = ctx.isRequested(kHitDistance);
    f.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    f.model = viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0));
    for (int c = 0; c < 3; ++c)
        f.normal[c] = viewOf(ports.input(gbuffer::kNormal)->image().plane(c));
    f.ao = spanOf(ports.overwrite(kAo, {size}).image().plane(0));
    f.hitDistance = spanOf(ports.overwrite(kHitDistance, {size}).image().plane(0));
    const auto counts = pixels.template forEach<kCounterCount>(
        size.width, size.height,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& w) { aoPixel(f, x, y, w); },
        "rt_ambient_occlusion");
    if (setup.intensity > 0.0f) {
        ctx.addWork("rays", counts[kRays]);
        ctx.addWork("pixels", counts[kPixels]);
    }
    ctx.addWork("skippedPixels", counts[kSkipped]);
}

}  // namespace fp::rtao
