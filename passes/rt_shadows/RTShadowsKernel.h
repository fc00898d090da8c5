#pragma once
// rt_shadows' per-pixel work written once for both backends: a pixel's set-up, each sample's
// shadow ray, what a blocked ray adds (transmission through the pixel's own object) and the
// resolve. The CPU's scalar reference (RTShadowsPass.cpp, lanes=false) builds its rows from
// setupPixel and sampleRay with T = float and traces them through Embree; its SIMD lanes
// (ShadowLanes.cpp) run the same setupPixel and sampleRay over float lanes, the same bits. The GPU's kernel (RTShadowsPass.cu) and the CPU's `traversal: "bvh"`
// run `run` below, tracing framepass's own BVH (foundation/Bvh.h) one pixel per thread: the
// same rays, the same tree, the same bits on both.
#include "foundation/Bvh.h"
#include "foundation/Camera.h"
#include "foundation/ExpLog.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Random.h"
#include "foundation/ShadingModel.h"
#include "framework/Pass.h"
#include "passes/rt_shadows/RTShadowsPass.h"
#include "passes/rt_shadows/ShadowRayGenerator.h"
#include "screenspace/GBuffer.h"
#include "shading/LightAttenuation.h"
#include "shading/RayOriginBias.h"

#include <cstdint>

namespace fp::shadow {

inline constexpr const char* kInstanceId = "instanceId";
inline constexpr const char* kShadow = "shadow";
inline constexpr const char* kTransmission = "transmission";
inline constexpr const char* kHitDistance = "hitDistance";
inline constexpr const char* kLightAttenuation = "lightAttenuation";

/// Subsurface-profile thickness is measured up to 5 cm (SSSS_MAX_TRANSMISSION_PROFILE_DISTANCE).
inline constexpr float kMaxProfileDistanceCm = 5.0f;

/// What the set-up and the rays need besides the pixel: the camera, the light, the biases.
struct RowContext {
    CameraView camera;
    Vec3d eyeOffset;  // the eye relative to the RayScene origin
    ShadowLightShape light;
    float maxBias, minBias;  // scene units
    bool transmission;       // the light's bTransmission
    uint32_t rngKey;         // Rng's per-frame, per-light part: pcgHash(frame ^ pcgHash(seed ^ …))
};

/// What the pass's parameters and the frame make of the light, the camera and the samples, for
/// either path.
struct FrameSetup {
    RowContext row;
    int spp;                       // samples per pixel
    float cm;                      // scene units per centimetre
    float lodStart, lodEnd;        // cm
};
FrameSetup setupFrame(const RTShadowsParams& params, PassContext& ctx);  // RTShadowsPass.cpp

/// The InstanceId buffer's value as an id, and CustomData.A as the subsurface opacity (1 without
/// the buffer), as a transmission ray reads them.
FP_HD inline uint32_t instanceIdOf(float stored) {
    return uint32_t(truncToInt(stored, 0, 1 << 30));
}

// algorithms §9.2: N·L ≤ 0 means "occluded" without a ray, except for hair, eye, two-sided foliage,
// subsurface (inferred: subsurface and subsurface profile) and rect lights.
// (T = float: one pixel's shading model; float lanes: a model a lane, LaneFloat.h.)
template <class T = float>
FP_HD inline MaskOf<T> cullsBackFacing(IntOf<T> model, LightType type) {
    if (type == LightType::Rect) return MaskOf<T>{};
    return !((model == kHair) | (model == kEye) | (model == kTwoSidedFoliage) | (model == kSubsurface) |
             (model == kSubsurfaceProfile));
}

template <class T = float>
FP_HD inline MaskOf<T> hasThicknessTransmission(IntOf<T> model) {
    return (model == kSubsurface) | (model == kHair);
}

/// Transmission through `thicknessCm` of a material of this opacity (algorithms §9.3):
/// exp(−density·thickness) with density = −0.05·ln(1 − min(opacity, 0.999)) per cm, which is
/// (1 − min(opacity, 0.999))^(0.05·thickness): ExpLog.h's power, the same bits on both backends.
FP_HD inline float transmittance(float opacity, float thicknessCm) {
    const float clear = 1.0f - (opacity < 0.999f ? opacity : 0.999f);
    return saturate(powFloat(clear, 0.05f * thicknessCm));
}

/// Hair's transmission: density 1 per cm, exp(−thickness) as 2^(−thickness·log₂e).
FP_HD inline float hairTransmittance(float thicknessCm) {
    const double y = -double(thicknessCm) * explog_terms::kInvLn2;
    return saturate(y < -1000.0 ? 0.0f : float(exp2Double(y > 0.0 ? 0.0 : y)));
}

/// Unreal's subsurface-profile thickness encoding: 1 − thickness/5 cm, saturated.
FP_HD inline float encodeThickness(float thicknessCm) {
    return saturate(1.0f - thicknessCm / kMaxProfileDistanceCm);
}

/// What stays the same for every sample of one pixel; T: float (one pixel) or float lanes
/// (LaneFloat.h: a vector of a row's pixels, ShadowLanes.cpp).
template <class T>
struct PixelOf {
    Vec3T<T> p;             // camera-relative position
    Vec3T<T> n;             // bias normal (hair: towards the light)
    Vec3T<T> toEye;         // unit
    T eyeDistance;
    IntOf<T> model;
    UIntOf<T> rng;          // the pixel's Rng state (Random.h), advanced per sample
};
using Pixel = PixelOf<float>;

/// Pixel x of row y's set-up from its depth, shading model and normal; false for unlit and sky
/// pixels and those the light cannot reach (they trace nothing, and the rest of `px` is not
/// meaningful there). The position is rebuilt from depth in double (double lanes for lanes).
template <class T>
FP_HD inline MaskOf<T> setupPixel(const RowContext& c, UIntOf<T> x, int y, T depth, T model,
                                  const Vec3T<T>& normal, PixelOf<T>& px) {
    using D = DoubleOf<T>;
    // Sky and unlit pixels: nothing to rebuild. (The id as truncToInt(model, 0, 255) gives it:
    // floorToIntOf is the same for lo = 0.)
    px.model = floorToIntOf(model, 0, 255);
    MaskOf<T> active = isLitSurfaceOf(depth, px.model);
    if (!anyLane(active)) return active;
    const Vec3T<D> offset = c.camera.translatedFromPixelOf(toDouble(toFloat(x)), double(y), toDouble(depth));
    const PixelSurfaceOf<T> surface = pixelSurfaceAt(c.eyeOffset, offset);
    const Vec3T<T>& p = surface.p;
    active = active & lightReaches(c.light, p);
    if (!anyLane(active)) return active;
    px.p = p;
    px.eyeDistance = surface.eyeDistance;
    px.toEye = surface.toEye;
    // Hair's GBuffer normal is its tangent: Unreal biases along the light instead.
    const MaskOf<T> hair = px.model == kHair;
    px.n = anyLane(hair) ? ifThenElse(hair, lightCentreDirection(c.light, p), normal) : normal;
    // Rng::fromKey(key, x, y): per-pixel streams.
    px.rng = pcgHashOf(x ^ UIntOf<T>(pcgHash(uint32_t(y) ^ c.rngKey)));
    return active;
}

/// One shadow ray: from org along the unit dir up to tfar.
template <class T>
struct ShadowRayOf {
    Vec3T<T> org, dir;
    T tfar;
};
using ShadowRay = ShadowRayOf<float>;

/// The pixel's next sample: draws its random pair (always, so every sample reads the same
/// stream) and returns false for a back-facing pixel the light culls (occluded without a ray).
template <class T>
FP_HD inline MaskOf<T> sampleRay(const RowContext& c, PixelOf<T>& px, ShadowRayOf<T>& ray) {
    const T u = nextFloatOf<T>(px.rng);
    const T v = nextFloatOf<T>(px.rng);
    const T NoL = dot(px.n, lightCentreDirection(c.light, px.p));
    const MaskOf<T> facesAway = NoL <= 0.0f;
    const MaskOf<T> traces = !(facesAway & cullsBackFacing<T>(px.model, c.light.type));
    if (!anyLane(traces)) return traces;
    // A transmissive pixel facing away starts on its back side.
    const MaskOf<T> backSide =
        c.transmission ? facesAway & (hasThicknessTransmission<T>(px.model) | (px.model == kSubsurfaceProfile))
                       : MaskOf<T>{};
    const Vec3T<T> o = biasedRayOrigin(px.p, px.toEye, px.eyeDistance, px.n, NoL, c.maxBias,
                                       c.minBias, backSide);
    const ShadowDirectionOf<T> sd = sampleLight(c.light, o, u, v);
    ray = {o, sd.dir, sd.tfar};
    return traces;
}

/// A pixel's sums over its samples.
struct Sums {
    float visibility = 0, transmission = 0, closestHit = -1;
};

/// What one traced sample adds to the pixel's sums. `scene` answers closest hits restricted to
/// one InstanceId (float instanceHit(org, dir, tfar, id): t or −1) and the farthest distance to
/// the scene's bounds; `opacity()` and `instance()` read the pixel's CustomData.A and InstanceId,
/// only where a transmission ray needs them. Returns the transmission rays it traced.
template <class Scene, class Opacity, class Instance>
FP_HD int addSample(const RowContext& c, const Scene& scene, const Pixel& px, const ShadowRay& ray,
                    bool blocked, float hitT, float cm, const Opacity& opacity,
                    const Instance& instance, Sums& r) {
    const int model = px.model;
    // A subsurface-profile pixel's transmission channel is its encoded thickness instead.
    const bool profile = c.transmission && model == kSubsurfaceProfile;
    int rays = 0;
    if (!blocked) {
        r.visibility += 1.0f;
        if (!profile) r.transmission += 1.0f;
    } else {
        if (hitT >= 0.0f && (r.closestHit < 0.0f || hitT < r.closestHit)) r.closestHit = hitT;
        if (c.transmission && hasThicknessTransmission(model)) {
            // algorithms §9.3: the inverted ray from the far end finds where the light enters the
            // pixel's own object; the thickness gives the transmittance, and a fully transmitted
            // sample counts as unoccluded.
            const float bound = scene.farthestDistance(ray.org);
            const float far = ray.tfar < bound ? ray.tfar : bound;
            const Vec3f start = ray.org + ray.dir * far;
            const float t = scene.instanceHit(start, -ray.dir, far, instance());
            ++rays;
            if (t >= 0.0f) {
                const float thicknessCm = (far - t) / cm;
                const float T = model == kHair ? hairTransmittance(thicknessCm)
                                               : transmittance(opacity(), thicknessCm);
                r.transmission += T;
                if (T == 1.0f) r.visibility += 1.0f;  // promoted to unoccluded
            }
        }
    }
    if (profile) {
        // Subsurface profile: the encoded thickness of its own object towards the light, up to
        // 5 cm (inferred simplification of Unreal's constant-tracking estimate, algorithms §9.3).
        const float reach = kMaxProfileDistanceCm * cm;
        const Vec3f start = ray.org + ray.dir * reach;
        const float t = scene.instanceHit(start, -ray.dir, reach, instance());
        ++rays;
        const float thicknessCm =
            t >= 0.0f ? (reach - t) / cm
                      : (dot(px.n, ray.dir) > 0.0f ? 0.0f : kMaxProfileDistanceCm);
        r.transmission += encodeThickness(thicknessCm);
    }
    return rays;
}

/// A pixel's outputs: the means over its samples, the visibility of far subsurface and hair pixels
/// blended towards their transmission (algorithms §9.3's LOD transition).
struct Resolved {
    float visibility, transmission;
};
FP_HD inline Resolved resolve(const Pixel& px, const Sums& sums, const FrameSetup& s) {
    const float transmission = sums.transmission / float(s.spp);
    float visibility = sums.visibility / float(s.spp);
    if (hasThicknessTransmission(px.model) && s.lodEnd > 0.0f) {
        const float width = s.lodEnd - s.lodStart;
        const float span = width > 1e-6f ? width : 1e-6f;
        const float f = saturate((px.eyeDistance / s.cm - s.lodStart) / span);
        visibility += (transmission - visibility) * f;
    }
    return {visibility, transmission};
}

/// The scene as addSample sees it, through the BVH.
struct BvhScene {
    BvhView bvh;
    FP_HD float farthestDistance(const Vec3f& p) const {
        return fp::farthestDistance(bvh.lo, bvh.hi, p);
    }
    FP_HD float instanceHit(const Vec3f& org, const Vec3f& dir, float tfar, uint32_t id) const {
        return traceBvh(bvh, org, dir, 0.0f, tfar, BvhQuery{false, true, id});
    }
};

/// Everything one frame's pixels read and write on the BVH path.
struct Frame {
    FrameSetup setup;
    BvhScene scene;
    bool wantDistance;
    PlaneView depth, normal[3], model, opacity, instance;  // opacity, instance: data null if absent
    PlaneSpan shadow, transmission, hitDistance, attenuation[4];  // attenuation: null if unasked
};

/// The work counters of the BVH path, as the CPU pass names them.
enum Counter { kRays, kTransmissionRays, kDistanceRays, kPixels, kSkipped, kCounterCount };

/// A pixel that traces nothing (unlit, sky, out of the light's reach): no light.
FP_HD inline void writeUnlit(const Frame& f, int x, int y) {
    f.shadow.at(x, y) = 0.0f;
    f.transmission.at(x, y) = 0.0f;
    f.hitDistance.at(x, y) = -1.0f;
    if (f.attenuation[0])
        for (int c = 0; c < 4; ++c) f.attenuation[c].at(x, y) = 0.0f;
}

/// A pixel's outputs from its sums over the samples.
FP_HD inline void writeResolved(const Frame& f, int x, int y, const Pixel& px, const Sums& sums) {
    const Resolved r = resolve(px, sums, f.setup);
    f.shadow.at(x, y) = r.visibility;
    f.transmission.at(x, y) = r.transmission;
    f.hitDistance.at(x, y) = sums.closestHit;
    if (f.attenuation[0]) {
        const LightAttenuation a =
            LightAttenuation::fromShadow(f.setup.row.light.type, r.visibility, r.transmission);
        f.attenuation[0].at(x, y) = a.r;
        f.attenuation[1].at(x, y) = a.g;
        f.attenuation[2].at(x, y) = a.b;
        f.attenuation[3].at(x, y) = a.a;
    }
}

/// Pixel (x, y)'s set-up from the frame's planes.
FP_HD inline bool setupFramePixel(const Frame& f, int x, int y, Pixel& px) {
    const Vec3f normal{f.normal[0].at(x, y), f.normal[1].at(x, y), f.normal[2].at(x, y)};
    return setupPixel(f.setup.row, x, y, f.depth.at(x, y), f.model.at(x, y), normal, px);
}

/// Whether a shadow ray is blocked, and where asked its closest occluder (−1: none or unasked).
FP_HD inline bool traceShadowRay(const Frame& f, const ShadowRay& ray, float& hitT) {
    const float t = traceBlocker(f.scene.bvh, ray.org, ray.dir, 0.0f, ray.tfar, f.wantDistance);
    hitT = f.wantDistance ? t : -1.0f;
    return t >= 0.0f;
}

/// What a traced sample of pixel (x, y) adds to its sums; returns the transmission rays.
FP_HD inline int addFrameSample(const Frame& f, int x, int y, const Pixel& px,
                                const ShadowRay& ray, bool blocked, float hitT, Sums& sums) {
    auto opacity = [&] { return f.opacity.data ? f.opacity.at(x, y) : 1.0f; };
    auto instance = [&] { return f.instance.data ? instanceIdOf(f.instance.at(x, y)) : 0u; };
    return addSample(f.setup.row, f.scene, px, ray, blocked, hitT, f.setup.cm, opacity, instance,
                     sums);
}

/// Pixel (x, y): its set-up, its samples traced through the BVH, its resolve. Its counts are kept
/// in 32 bits until the end: fewer registers live across the traversal (64-bit counters held ten).
FP_HD inline void shadowPixel(const Frame& f, int x, int y, WorkCounts<kCounterCount>& work) {
    Pixel px;
    if (!setupFramePixel(f, x, y, px)) {
        ++work.value[kSkipped];
        writeUnlit(f, x, y);
        return;
    }
    uint32_t rays = 0, distanceRays = 0, transmissionRays = 0;
    Sums sums;
    for (int sample = 0; sample < f.setup.spp; ++sample) {
        ShadowRay ray;
        if (!sampleRay(f.setup.row, px, ray)) continue;
        ++rays;
        float hitT;
        const bool blocked = traceShadowRay(f, ray, hitT);
        distanceRays += blocked && f.wantDistance;
        transmissionRays += uint32_t(addFrameSample(f, x, y, px, ray, blocked, hitT, sums));
    }
    writeResolved(f, x, y, px, sums);
    ++work.value[kPixels];
    work.value[kRays] += rays;
    work.value[kDistanceRays] += distanceRays;
    work.value[kTransmissionRays] += transmissionRays;
}

/// The frame's planes and the pass's set-up bound for the BVH path.
template <class Ports>
Frame bindFrame(PassContext& ctx, const Ports& ports, const FrameSetup& setup) {
    const Extent size = ctx.frame().extent;
    Frame f{};
    f.setup = setup;
    f.scene.bvh = ports.bvh();
    f.wantDistance = ctx.isRequested(kHitDistance);
    f.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    for (int c = 0; c < 3; ++c) f.normal[c] = viewOf(ports.input(gbuffer::kNormal)->image().plane(c));
    f.model = viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0));
    if (const auto* custom = ports.input(gbuffer::kCustomData))
        f.opacity = viewOf(custom->image().plane(3));
    if (const auto* ids = ports.input(kInstanceId)) f.instance = viewOf(ids->image().plane(0));
    // Every output is written at every pixel (writeUnlit or writeResolved).
    f.shadow = spanOf(ports.overwrite(kShadow, {size}).image().plane(0));
    f.transmission = spanOf(ports.overwrite(kTransmission, {size}).image().plane(0));
    f.hitDistance = spanOf(ports.overwrite(kHitDistance, {size}).image().plane(0));
    if (auto* att = ports.overwriteIfRequested(kLightAttenuation, {size}))
        for (int c = 0; c < 4; ++c) f.attenuation[c] = spanOf(att->image().plane(c));
    return f;
}

/// Reports the pass's work counters to `ctx` (either path).
inline void addWork(PassContext& ctx, const uint64_t (&work)[kCounterCount]) {
    ctx.addWork("rays", work[kRays]);
    ctx.addWork("transmissionRays", work[kTransmissionRays]);
    ctx.addWork("distanceRays", work[kDistanceRays]);
    ctx.addWork("pixels", work[kPixels]);
    ctx.addWork("skippedPixels", work[kSkipped]);
}

/// The whole pass on the BVH path, one pixel at a time through `pixels`: CpuPixels for the CPU's
/// traversal "bvh", CudaPixels (a thread a pixel) on the GPU.
template <class Ports, class Pixels>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const FrameSetup& setup) {
    const Frame f = bindFrame(ctx, ports, setup);
    const Extent size = ctx.frame().extent;
    const auto counts = pixels.template forEach<kCounterCount>(
        size.width, size.height,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& w) { shadowPixel(f, x, y, w); },
        "rt_shadows");
    uint64_t work[kCounterCount];
    for (int i = 0; i < kCounterCount; ++i) work[i] = counts[i];
    addWork(ctx, work);
}

}  // namespace fp::shadow
