#include "passes/rt_shadows/RTShadowsPass.h"

#include "passes/common/GBuffer.h"
#include "passes/core/Random.h"
#include "passes/core/RayScene.h"
#include "passes/core/ShadingModel.h"
#include "passes/core/Tiles.h"
#include "passes/lighting/LightAttenuation.h"
#include "passes/lighting/NamedLight.h"
#include "passes/rt_shadows/ShadowRayGenerator.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kInstanceId = "instanceId";
constexpr const char* kShadow = "shadow";
constexpr const char* kTransmission = "transmission";
constexpr const char* kHitDistance = "hitDistance";
constexpr const char* kLightAttenuation = "lightAttenuation";

constexpr uint32_t kSeed = 0x52545348u;    // "RTSH"
constexpr float kMinNormalBiasCm = 0.01f;  // reference §9.1: r.RayTracing.NormalBias min 0.01

// Each light draws its own random numbers, so adding a light leaves the others' shadows alone.
uint32_t lightSeed(const std::string& name) {
    uint32_t h = 2166136261u;  // FNV-1a
    for (unsigned char c : name)
        h = (h ^ c) * 16777619u;
    return kSeed ^ h;
}

// Reference §9.2: N·L ≤ 0 means "occluded" without a ray, except for hair, eye, two-sided foliage,
// subsurface (inferred: subsurface and subsurface profile) and rect lights.
bool cullsBackFacing(int model, LightType type) {
    if (type == LightType::Rect)
        return false;
    return model != kHair && model != kEye && model != kTwoSidedFoliage && model != kSubsurface &&
           model != kSubsurfaceProfile;
}

bool hasThicknessTransmission(int model) {
    return model == kSubsurface || model == kHair;
}

// One pixel of a packet row: what stays the same for all its samples.
struct PixelSetup {
    bool active = false;
    Vec3f p;      // reconstructed position, relative to the RayScene origin
    Vec3f n;      // normal used for biasing (the light direction for hair)
    Vec3f toEye;  // unit, from the pixel to the eye
    float eyeDistance = 0;
    int model = 0;
    float opacity = 1;
    uint32_t instance = 0;
};

struct PixelResult {
    float visibility = 0, transmission = 0, closestHit = -1;
};

// Work counters of one tile.
struct TileWork {
    uint64_t rays = 0, transmissionRays = 0, distanceRays = 0, pixels = 0, skipped = 0;
};

// The output planes of the pass.
struct ShadowOutputs {
    Plane& shadow;
    Plane& transmission;
    Plane& hitDistance;
    Image& attenuation;
};

// One light's shadow rays over the frame: the per-pixel setup, the rays of one sample, what a
// blocked ray adds (transmission through the pixel's own object) and the per-pixel resolve,
// driven one packet of kPacketSize neighbouring pixels at a time.
class ShadowTracer {
public:
    ShadowTracer(const RTShadowsParams& params,
                 PassContext& ctx,
                 const RayScene& rs,
                 const Light& light)
        : mParams(params),
          mRs(rs),
          mLight(light),
          mCam(ctx.frame().camera.current),
          mGenerator(light, mRs.origin()),
          mCm(float(mRs.scene().centimetre())),
          mMaxBias(std::max(params.normalBias, kMinNormalBiasCm) * mCm),
          mMinBias(kMinNormalBiasCm * mCm),
          mSpp(params.samplesPerPixel > 0 ? params.samplesPerPixel : light.samplesPerPixel),
          mSeed(lightSeed(light.name)),
          mEyeOffset(mCam.position - mRs.origin()),
          mFrame(ctx.frame().number),
          mDepth(ctx.input(gbuffer::kDepth)->image().plane(0)),
          mNormal(ctx.input(gbuffer::kNormal)->image()),
          mModels(ctx.input(gbuffer::kShadingModel)->image().plane(0)),
          mCustomData(ctx.input(gbuffer::kCustomData)),
          mInstances(ctx.input(kInstanceId)),
          mWantDistance(ctx.isRequested(kHitDistance)) {}

    /// Pixels [x0, x1) of row py (x1 − x0 ≤ kTileSize). Each sample's rays are gathered from the
    /// pixels that trace one (unlit, sky, unreachable and back-facing pixels trace none) and
    /// traced in full packets of kPacketSize, as the bare Embree loop traces them: a packet of
    /// eight neighbouring pixels, most of them idle at a shadow's or the light's edge, costs a
    /// full packet's traversal. Every pixel still draws its own random stream in sample order, so
    /// the result is that of one ray at a time.
    void traceRow(int x0, int x1, int py, const ShadowOutputs& out, TileWork& work) const {
        const int n = x1 - x0;
        std::array<PixelSetup, kTileSize> px;
        std::array<PixelResult, kTileSize> res;
        std::array<Rng, kTileSize> rng;
        int active[kTileSize], activeCount = 0;
        for (int i = 0; i < n; ++i) {
            px[i] = setupPixel(x0 + i, py);
            res[i] = {};
            if (!px[i].active) {
                ++work.skipped;
                continue;
            }
            ++work.pixels;
            rng[i] = Rng(mFrame, x0 + i, py, mSeed);  // per-pixel streams
            active[activeCount++] = i;
        }
        // One sample's rays, gathered, and the pixel each belongs to; padded to whole packets.
        std::array<Ray, kTileSize + kPacketSize> ray;
        int owner[kTileSize];
        bool blocked[kTileSize + kPacketSize];
        float hitT[kTileSize + kPacketSize];
        for (int sample = 0; sample < mSpp && activeCount > 0; ++sample) {
            int rays = 0;
            for (int k = 0; k < activeCount; ++k) {
                const int i = active[k];
                if (shadowRay(px[i], rng[i], ray[rays]))
                    owner[rays++] = i;
            }
            work.rays += uint64_t(rays);
            for (int first = 0; first < rays; first += kPacketSize)
                trace(&ray[first], std::min(kPacketSize, rays - first), &blocked[first],
                      &hitT[first], work);
            for (int k = 0; k < rays; ++k)
                addSample(px[owner[k]], ray[k], blocked[k], hitT[k], res[owner[k]], work);
        }
        for (int i = 0; i < n; ++i)
            resolvePixel(px[i], res[i], x0 + i, py, out);
    }

private:
    // What stays the same for all samples of pixel (x, py); inactive for unlit and sky pixels and
    // those the light cannot reach.
    PixelSetup setupPixel(int x, int py) const {
        PixelSetup s;
        const double d = mDepth.at(x, py);
        const float model = mModels.at(x, py);
        if (!isLitSurface(d, model))
            return s;  // sky and unlit pixels: nothing to rebuild
        const Vec3d offset = mCam.translatedFromPixel(x, py, d);
        const Vec3f p(mEyeOffset + offset);
        if (!mGenerator.reaches(p))
            return s;
        s.active = true;
        s.p = p;
        const double eyeDistance = length(offset);
        s.eyeDistance = float(eyeDistance);
        s.toEye = Vec3f(-offset / eyeDistance);
        s.n = gbuffer::worldNormalAt(mNormal, x, py);
        s.model = int(model);
        // Hair's GBuffer normal is its tangent: Unreal biases along the light instead.
        if (s.model == kHair)
            s.n = mGenerator.centreDirection(s.p);
        s.opacity = mCustomData ? mCustomData->image().plane(3).at(x, py) : 1.0f;
        s.instance =
            mInstances ? uint32_t(truncToInt(mInstances->image().plane(0).at(x, py), 0, 1 << 30))
                       : 0u;
        return s;
    }

    // One sample's ray; false when a back-facing pixel is occluded without a ray. The two
    // random numbers are drawn either way, so every sample of a pixel reads the same stream.
    bool shadowRay(const PixelSetup& s, Rng& rng, Ray& ray) const {
        const float u = rng.nextFloat(), v = rng.nextFloat();
        const Vec3f Lc = mGenerator.centreDirection(s.p);
        const float NoL = dot(s.n, Lc);
        if (NoL <= 0.0f && cullsBackFacing(s.model, mLight.type))
            return false;
        // Reference §9.2: towards the camera by max(1e-4·distance, bias), then along the normal
        // by lerp(bias, 0.01 cm, N·L); a transmissive pixel facing away starts on its back side
        // instead.
        Vec3f o = s.p + s.toEye * std::max(1e-4f * s.eyeDistance, mMaxBias);
        const float nb = mMaxBias + (mMinBias - mMaxBias) * std::clamp(NoL, 0.0f, 1.0f);
        const bool backSide = mParams.transmission && NoL <= 0.0f &&
                              (hasThicknessTransmission(s.model) || s.model == kSubsurfaceProfile);
        o += s.n * (backSide ? -nb : nb);
        const ShadowDirection sd = mGenerator.sample(o, u, v);
        ray = Ray{o, sd.dir, 0.0f, sd.tfar};
        return true;
    }

    // Occlusion of the first `count` (1 to kPacketSize) of the rays, and where a blocked ray's
    // distance is wanted (the denoiser's input) its closest hit (−1: none), found in the same
    // traversal; as a packet or one ray at a time, with the same result.
    void trace(const Ray* ray, int count, bool blocked[], float hitT[], TileWork& work) const {
        if (mParams.rayPackets) {
            bool inPacket[kPacketSize];
            for (int i = 0; i < kPacketSize; ++i)
                inPacket[i] = i < count;
            if (mWantDistance) {
                mRs.occludedWithDistance8(ray, inPacket, blocked, hitT);
            } else {
                mRs.occluded8(ray, inPacket, blocked);
                std::fill(hitT, hitT + count, -1.0f);
            }
        } else {
            for (int i = 0; i < count; ++i) {
                blocked[i] = mRs.occluded(ray[i].org, ray[i].dir, ray[i].tnear, ray[i].tfar);
                hitT[i] = -1.0f;
                if (mWantDistance && blocked[i]) {
                    const RayHit h =
                        mRs.intersect(ray[i].org, ray[i].dir, ray[i].tnear, ray[i].tfar);
                    hitT[i] = h.hit ? h.t : -1.0f;
                }
            }
        }
        if (mWantDistance)
            for (int i = 0; i < count; ++i)
                work.distanceRays += blocked[i];
    }

    // What one traced sample adds to its pixel.
    void addSample(const PixelSetup& s,
                   const Ray& ray,
                   bool blocked,
                   float hitT,
                   PixelResult& r,
                   TileWork& work) const {
        // A subsurface-profile pixel's transmission channel is its encoded thickness instead.
        const bool profile = mParams.transmission && s.model == kSubsurfaceProfile;
        if (!blocked) {
            r.visibility += 1.0f;
            if (!profile)
                r.transmission += 1.0f;
        } else {
            if (hitT >= 0.0f && (r.closestHit < 0.0f || hitT < r.closestHit))
                r.closestHit = hitT;
            if (mParams.transmission && hasThicknessTransmission(s.model))
                addThicknessTransmission(s, ray, r, work);
        }
        if (profile)
            r.transmission += profileThickness(s, ray, work);
    }

    // Reference §9.3: the inverted ray from the far end finds where the light enters the pixel's
    // own object; the thickness gives the transmittance (hair: density 1 per cm), and a fully
    // transmitted sample counts as unoccluded.
    void addThicknessTransmission(const PixelSetup& s,
                                  const Ray& ray,
                                  PixelResult& r,
                                  TileWork& work) const {
        const float far = std::min(ray.tfar, mRs.farthestDistance(ray.org));
        const Vec3f start = ray.org + ray.dir * far;
        const RayHit h = mRs.intersectInstance(start, -ray.dir, 0.0f, far, s.instance);
        ++work.transmissionRays;
        if (!h.hit)
            return;
        const float thicknessCm = (far - h.t) / mCm;
        const float T = s.model == kHair ? std::clamp(std::exp(-thicknessCm), 0.0f, 1.0f)
                                         : RTShadowsPass::transmittance(s.opacity, thicknessCm);
        r.transmission += T;
        if (T == 1.0f)
            r.visibility += 1.0f;  // promoted to unoccluded
    }

    // Subsurface profile: the encoded thickness of its own object towards the light, up to 5 cm
    // (inferred simplification of Unreal's constant-tracking estimate, reference §9.3).
    float profileThickness(const PixelSetup& s, const Ray& ray, TileWork& work) const {
        const float reach = RTShadowsPass::kMaxProfileDistanceCm * mCm;
        const Vec3f start = ray.org + ray.dir * reach;
        const RayHit h = mRs.intersectInstance(start, -ray.dir, 0.0f, reach, s.instance);
        ++work.transmissionRays;
        const float thicknessCm =
            h.hit ? (reach - h.t) / mCm
                  : (dot(s.n, ray.dir) > 0.0f ? 0.0f : RTShadowsPass::kMaxProfileDistanceCm);
        return RTShadowsPass::encodeThickness(thicknessCm);
    }

    // The pixel's means over its samples, with far subsurface pixels blended towards
    // transmission (reference §9.3), written with their light-attenuation encoding.
    void resolvePixel(const PixelSetup& s,
                      const PixelResult& r,
                      int x,
                      int py,
                      const ShadowOutputs& out) const {
        if (!s.active) {
            out.hitDistance.at(x, py) = -1.0f;
            return;  // shadow, transmission and attenuation stay 0: no light
        }
        float visibility = r.visibility / float(mSpp);
        const float transmission = r.transmission / float(mSpp);
        if (hasThicknessTransmission(s.model) && mParams.lodTransitionEnd > 0.0f) {
            const float span =
                std::max(mParams.lodTransitionEnd - mParams.lodTransitionStart, 1e-6f);
            const float f =
                std::clamp((s.eyeDistance / mCm - mParams.lodTransitionStart) / span, 0.0f, 1.0f);
            visibility += (transmission - visibility) * f;
        }
        out.shadow.at(x, py) = visibility;
        out.transmission.at(x, py) = transmission;
        out.hitDistance.at(x, py) = r.closestHit;
        LightAttenuation::fromShadow(mLight.type, visibility, transmission)
            .store(out.attenuation, x, py);
    }

    const RTShadowsParams& mParams;
    const RayScene& mRs;
    const Light& mLight;
    const CameraView& mCam;
    const ShadowRayGenerator mGenerator;
    const float mCm, mMaxBias, mMinBias;
    const int mSpp;
    const uint32_t mSeed;
    const Vec3d mEyeOffset;  // the eye relative to the RayScene origin (usually zero)
    const int64_t mFrame;
    const Plane& mDepth;
    const Image& mNormal;
    const Plane& mModels;
    const Texture* mCustomData;
    const Texture* mInstances;
    const bool mWantDistance;  // closest-hit rays only where a blocked ray's distance is read
};

}  // namespace

ParamSpec<RTShadowsParams> RTShadowsPass::paramSpec() {
    ParamSpec<RTShadowsParams> s;
    s.add("light", &Params::light, "name of the light (\"\" = the scene's only light)");
    s.add("samplesPerPixel", &Params::samplesPerPixel,
          "shadow rays per pixel; −1 = the light's own samplesPerPixel")
        .range(-1, 64)
        .cvar("r.RayTracing.Shadow.SamplesPerPixel");
    s.add("normalBias", &Params::normalBias, "largest normal/camera bias, cm (at N·L = 0)")
        .range(0.01, 1e6)
        .cvar("r.RayTracing.NormalBias");
    s.add("transmission", &Params::transmission,
          "light bTransmission: subsurface and hair pixels measure their own thickness");
    s.add("lodTransitionStart", &Params::lodTransitionStart,
          "subsurface visibility starts blending towards transmission, cm")
        .range(0.0, 1e9)
        .cvar("r.RayTracing.Shadows.LODTransitionStart");
    s.add("lodTransitionEnd", &Params::lodTransitionEnd, "... and is transmission from here, cm")
        .range(0.0, 1e9)
        .cvar("r.RayTracing.Shadows.LODTransitionEnd");
    s.add("rayPackets", &Params::rayPackets,
          "trace rtcOccluded8 packets of 8 neighbouring pixels (false: one ray at a time; same "
          "result bit for bit)");
    return s;
}

PassIO RTShadowsPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit and sky pixels are skipped"),
        gbuffer::customDataInput("A = opacity of subsurface models: the transmission density",
                                 true),
        {.name = kInstanceId,
         .channels = {"Y"},
         .optional = true,
         .captureDefault = "InstanceId",
         .doc = "the pixel's own object, whose thickness the transmission ray measures"},
    };
    io.outputs = {
        {.name = kShadow,
         .channels = {"Y"},
         .doc = "visibility: fraction of shadow rays unblocked"},
        {.name = kTransmission,
         .channels = {"Y"},
         .doc = "subsurface term: mean exp(−density·thickness) (subsurface, hair), encoded "
                "thickness 1 − d/5 cm (subsurface profile), else the visibility"},
        {.name = kHitDistance,
         .channels = {"Y"},
         .doc = "closest occluder distance over the samples, scene units; −1 = no occluder"},
        {.name = kLightAttenuation,
         .channels = {"R", "G", "B", "A"},
         .doc = "Unreal's light-attenuation encoding (reference §9.5), √ of the faded shadow"},
    };
    io.needsCamera = true;
    io.needsScene = true;
    io.workUnit = "rays";
    return io;
}

float RTShadowsPass::transmittance(float opacity, float thicknessCm) {
    const float density = -0.05f * std::log(1.0f - std::min(opacity, 0.999f));
    return std::clamp(std::exp(-density * thicknessCm), 0.0f, 1.0f);
}

float RTShadowsPass::encodeThickness(float thicknessCm) {
    return std::clamp(1.0f - thicknessCm / kMaxProfileDistanceCm, 0.0f, 1.0f);
}

void RTShadowsPass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const RayScene& rs = ctx.scene();
    const Light& light = namedLight(rs.scene().lights, mParams.light);
    const ShadowTracer tracer(mParams, ctx, rs, light);
    const Extent size = frame.extent;
    const ShadowOutputs out{ctx.output(kShadow, {size}).image().plane(0),
                            ctx.output(kTransmission, {size}).image().plane(0),
                            ctx.output(kHitDistance, {size}).image().plane(0),
                            ctx.output(kLightAttenuation, {size}).image()};
    forEachTile(size.width, size.height, [&](const Tile& t) {
        TileWork work;
        for (int py = t.y0; py < t.y1; ++py)
            tracer.traceRow(t.x0, t.x1, py, out, work);
        ctx.addWork("rays", work.rays);
        ctx.addWork("transmissionRays", work.transmissionRays);
        ctx.addWork("distanceRays", work.distanceRays);
        ctx.addWork("pixels", work.pixels);
        ctx.addWork("skippedPixels", work.skipped);
    });
}

}  // namespace fp
