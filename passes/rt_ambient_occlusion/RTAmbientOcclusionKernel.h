#pragma once
// rt_ambient_occlusion's per-pixel work (algorithms §12.1, Unreal 4.27's
// RayTracingAmbientOcclusionRGS): a pixel's set-up — its position from depth, its geometric
// normal from the neighbours' depths, how far its shading normal leans from it — each sample's
// cosine-weighted ray about the geometric normal with its weight, and the resolve. The set-up and
// the rays are templates on the number type: float for one pixel, float lanes (LaneFloat.h) for
// a row's pixels a vector (AmbientOcclusionLanes.cpp), the same bits. The CPU's Embree path
// batches their rays into packets, and run() traces them one pixel at a time through framepass's
// BVH (Bvh.h), on the CPU (traversal "bvh") and on the GPU (RTAmbientOcclusionPass.cu), the same
// code.
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

/// What stays the same for every sample of one pixel; T: float (one pixel) or float lanes
/// (LaneFloat.h: a vector of a row's pixels, RTAOLanes.cpp).
template <class T>
struct PixelOf {
    Vec3T<T> p;              // position relative to the RayScene origin
    Vec3T<T> shading;        // the GBuffer normal, unit
    Vec3T<T> geometric;      // from the neighbours' depths, facing the camera
    Vec3T<T> tangent, bitangent;  // orthonormalBasis(geometric): the rays' frame
    Vec3T<T> toEye;          // unit
    T eyeDistance;
    T shadingDotGeometric;   // how much of the shading lobe the geometric hemisphere holds
    UIntOf<T> rng;
};
using Pixel = PixelOf<float>;

/// sinh(x)/x = Σ x^{2k}/(2k+1)! for 0 ≤ x ≤ 2λ (|a + b| ≤ 2), by Horner in x² over 16 terms (the
/// last is below 10⁻¹⁵ of the sum at x = 2λ): no division and no exponential, so a pixel's lobe
/// overlap costs a few multiplications. D: double or double lanes.
template <class D>
FP_HD constexpr D sinhOverX(D x) {
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
    const D y = x * x;
    D sum = 0.0;
    for (int k = 15; k >= 0; --k) sum = sum * y + kInverseOddFactorial[k];
    return sum;
}

/// A cosine lobe's overlap with itself, sinh(2λ)/(2λ): the ratio's denominator, once.
inline constexpr double kSelfOverlap = sinhOverX(2.0 * kCosineLobeSharpness);

/// The overlap of two clamped cosine lobes about unit a and b as spherical Gaussians, over a
/// lobe's overlap with itself: ∫G_a·G_b = 4π·e^{−2λ}·sinh(d)/d with d = λ|a + b|, so the ratio is
/// (sinh(d)/d)·(2λ/sinh(2λ)), 1 for a = b, saturated.
template <class T>
FP_HD inline T lobeOverlap(const Vec3T<T>& a, const Vec3T<T>& b) {
    using D = DoubleOf<T>;
    const Vec3T<T> s = a + b;
    const D d = kCosineLobeSharpness * sqrtOf(toDouble(dot(s, s)));
    const D ratio = sinhOverX(d) / kSelfOverlap;
    return toFloat(ifThenElse(D(1.0) < ratio, D(1.0), ratio));
}

/// The depths of a pixel's four neighbours, as geometricNormal reads them: 0 (no surface) for a
/// neighbour beyond the image's edge.
template <class T>
struct NeighbourDepths {
    T right, left, below, above;  // x + 1, x − 1, y + 1, y − 1
};

/// The surface normal the depth buffer gives at (x, y) (algorithms §12.1): of the vectors to the
/// left and right neighbours the shorter, the same up and down, crossed and turned towards the
/// camera. The shading normal where a side has no surface on either hand (the screen's edge, sky)
/// or the vectors are parallel, and for two-sided foliage (thin: its faces bound nothing). With
/// lanes, every lane's choices are selects.
template <class T>
FP_HD FP_HOT_INLINE Vec3T<T> geometricNormal(const FrameSetup& s, UIntOf<T> x, int y,
                                             const NeighbourDepths<T>& depths,
                                             const Vec3T<DoubleOf<T>>& centre,
                                             const Vec3T<T>& shading, IntOf<T> model,
                                             const Vec3T<T>& toEye) {
    using D = DoubleOf<T>;
    using V3 = Vec3T<D>;
    const MaskOf<T> foliage = model == kTwoSidedFoliage;
    if (!anyLane(!foliage)) return shading;
    const D px = toDouble(toFloat(x));
    // A neighbour's surface where it has one (a lit depth; 0 beyond the edge has none).
    auto neighbour = [&](D nx, double ny, T depth, V3& q) {
        const D d = toDouble(depth);
        q = s.camera.translatedFromPixelOf(nx, ny, d);
        return (D(0.0) < d) & !isInfOf(d);
    };
    // The shorter of the two one-sided differences along an axis (either, where only one exists);
    // false where neither side has a surface.
    auto along = [&](D ax, double ay, T afterDepth, D bx, double by, T beforeDepth, V3& v) {
        V3 after, before;
        const auto a = neighbour(ax, ay, afterDepth, after);
        const auto b = neighbour(bx, by, beforeDepth, before);
        const V3 forward = after - centre, backward = centre - before;
        const auto forwardShorter = dot(forward, forward) < dot(backward, backward);
        v = ifThenElse(!b, forward, ifThenElse(!a, backward, ifThenElse(forwardShorter, forward, backward)));
        return a | b;
    };
    V3 h, v;
    const auto haveH = along(px + 1.0, double(y), depths.right, px - 1.0, double(y), depths.left, h);
    const auto haveV = along(px, double(y + 1), depths.below, px, double(y - 1), depths.above, v);
    const V3 n = cross(h, v);
    const D len = length(n);
    const Vec3T<T> g{toFloat(n.x / len), toFloat(n.y / len), toFloat(n.z / len)};
    const Vec3T<T> facing = ifThenElse(dot(g, toEye) < 0.0f, -g, g);
    const MaskOf<T> ok = toFloatMask(haveH & haveV & (D(0.0) < len)) & !foliage;
    return ifThenElse(ok, facing, shading);
}

/// Pixel x of row y's set-up from its depth, shading model, normal and neighbours' depths; false
/// for sky and unlit pixels (they trace nothing, and the rest of `px` is not meaningful there).
template <class T>
FP_HD FP_HOT_INLINE MaskOf<T> setupPixel(const FrameSetup& s, UIntOf<T> x, int y, T depth, T model,
                                         const Vec3T<T>& normal, const NeighbourDepths<T>& around,
                                         PixelOf<T>& px) {
    using D = DoubleOf<T>;
    // The shading model's id as truncToInt(model, 0, 255) gives it (floorToIntOf is the same for
    // lo = 0).
    const IntOf<T> id = floorToIntOf(model, 0, 255);
    const MaskOf<T> lit = isLitSurfaceOf(depth, id);
    if (!anyLane(lit)) return lit;
    const Vec3T<D> offset = s.camera.translatedFromPixelOf(toDouble(toFloat(x)), double(y), toDouble(depth));
    const PixelSurfaceOf<T> surface = pixelSurfaceAt(s.eyeOffset, offset);
    px.p = surface.p;
    px.eyeDistance = surface.eyeDistance;
    px.toEye = surface.toEye;
    px.shading = normal;
    px.geometric = geometricNormal(s, x, y, around, offset, px.shading, id, px.toEye);
    px.shadingDotGeometric = lobeOverlap(px.shading, px.geometric);
    orthonormalBasis(px.geometric, px.tangent, px.bitangent);
    // Rng::fromKey(key, x, y): per-pixel streams.
    px.rng = pcgHashOf(x ^ UIntOf<T>(pcgHash(uint32_t(y) ^ s.rngKey)));
    return lit;
}

/// Pixel (x, y)'s set-up read from the frame's planes (one pixel: the scalar reference, the GPU).
FP_HD FP_HOT_INLINE bool setupPixel(const FrameSetup& s, const PlaneView& depth, const PlaneView& model,
                                    const PlaneView (&normal)[3], int x, int y, Pixel& px) {
    if (!isLitSurface(depth.at(x, y), model.at(x, y))) return false;  // nothing more to read
    auto depthAt = [&](int nx, int ny) {
        return nx < 0 || ny < 0 || nx >= depth.width || ny >= depth.height ? 0.0f : depth.at(nx, ny);
    };
    const NeighbourDepths<float> around{depthAt(x + 1, y), depthAt(x - 1, y), depthAt(x, y + 1),
                                        depthAt(x, y - 1)};
    return setupPixel<float>(s, uint32_t(x), y, depth.at(x, y), model.at(x, y),
                             {normal[0].at(x, y), normal[1].at(x, y), normal[2].at(x, y)}, around, px);
}

/// One AO ray and its weight: cosine-distributed about the geometric normal (pdf ∝ cosθ there),
/// weighted by max(N_shading·dir, 0.05) / max(pdf, 0.05) so a shading normal that leans away
/// counts its own cosine (on a flat surface every weight is 1).
template <class T>
struct AoRayOf {
    Vec3T<T> org, dir;
    T weight;
};
using AoRay = AoRayOf<float>;
template <class T>
FP_HD FP_HOT_INLINE AoRayOf<T> sampleRay(const FrameSetup& s, PixelOf<T>& px) {
    const T u = nextFloatOf<T>(px.rng);
    const T v = nextFloatOf<T>(px.rng);
    // cosineHemisphere(px.geometric, u, v), its frame built once per pixel.
    T x, y;
    concentricDisk(u, v, x, y);
    const T z = sqrtOf(maxLike(T(0.0f), 1.0f - x * x - y * y));
    const Vec3T<T> dir = normalize(px.tangent * x + px.bitangent * y + px.geometric * z);
    const T NoL = dot(px.shading, dir);
    const T pdf = dot(px.geometric, dir);
    const T weight = ifThenElse(NoL > 0.05f, NoL, T(0.05f)) / ifThenElse(pdf > 0.05f, pdf, T(0.05f));
    const Vec3T<T> org = biasedRayOrigin(px.p, px.toEye, px.eyeDistance, px.shading, NoL,
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

/// Pixel (x, y) through the BVH: its set-up, each sample's ray (an any-hit query, or where the
/// hit distance is read a closest-hit one: traceBlocker), its resolve.
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
        const float t = traceBlocker(f.bvh, r.org, r.dir, 0.0f, f.setup.radius, f.wantDistance);
        sums.add(f.setup, r.weight, t >= 0.0f, f.wantDistance ? t : -1.0f);
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
