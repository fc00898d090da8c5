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
    const CameraView& cam = frame.camera.current;
    const RayScene& rs = ctx.scene();
    const Light& light = namedLight(rs.scene(), mParams.light);
    const ShadowRayGenerator generator(light, rs.origin());
    const float cm = float(rs.scene().centimetre());
    const float maxBias = std::max(mParams.normalBias, kMinNormalBiasCm) * cm;
    const float minBias = kMinNormalBiasCm * cm;
    const int spp = mParams.samplesPerPixel > 0 ? mParams.samplesPerPixel : light.samplesPerPixel;
    const uint32_t seed = lightSeed(light.name);
    // The eye relative to the RayScene origin (usually the eye itself: zero).
    const Vec3d eyeOffset = cam.position - rs.origin();

    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Image& normal = ctx.input(gbuffer::kNormal)->image();
    const Plane& models = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Texture* customData = ctx.input(gbuffer::kCustomData);
    const Texture* instances = ctx.input(kInstanceId);
    const Extent size = frame.extent;
    Plane& shadowOut = ctx.output(kShadow, {size}).image().plane(0);
    Plane& transmissionOut = ctx.output(kTransmission, {size}).image().plane(0);
    Plane& hitOut = ctx.output(kHitDistance, {size}).image().plane(0);
    Image& attenuationOut = ctx.output(kLightAttenuation, {size}).image();
    // Closest-hit rays only where a blocked ray's distance is wanted (the denoiser's input).
    const bool wantDistance = ctx.isRequested(kHitDistance);

    forEachTile(size.width, size.height, [&](const Tile& t) {
        uint64_t rays = 0, transmissionRays = 0, distanceRays = 0, pixels = 0, skipped = 0;
        for (int py = t.y0; py < t.y1; ++py)
            for (int x0 = t.x0; x0 < t.x1; x0 += kPacketSize) {
                std::array<PixelSetup, kPacketSize> px{};
                std::array<PixelResult, kPacketSize> res{};
                // Per-pixel streams: packets and single rays draw the same numbers.
                auto pixelRng = [&](int i) { return Rng(frame.number, x0 + i, py, seed); };
                std::array<Rng, kPacketSize> rng{pixelRng(0), pixelRng(1), pixelRng(2),
                                                 pixelRng(3), pixelRng(4), pixelRng(5),
                                                 pixelRng(6), pixelRng(7)};
                static_assert(kPacketSize == 8);
                for (int i = 0; i < kPacketSize && x0 + i < t.x1; ++i) {
                    const int x = x0 + i;
                    const double d = depth.at(x, py);
                    const float model = models.at(x, py);
                    PixelSetup& s = px[i];
                    const Vec3d offset = cam.translatedFromPixel(x, py, d);
                    if (!isLitSurface(d, model) || !generator.reaches(Vec3f(eyeOffset + offset))) {
                        ++skipped;
                        continue;
                    }
                    s.active = true;
                    s.p = Vec3f(eyeOffset + offset);
                    s.eyeDistance = float(length(offset));
                    s.toEye = Vec3f(-offset / length(offset));
                    s.n = gbuffer::worldNormalAt(normal, x, py);
                    s.model = int(model);
                    // Hair's GBuffer normal is its tangent: Unreal biases along the light instead.
                    if (s.model == kHair)
                        s.n = generator.centreDirection(s.p);
                    s.opacity = customData ? customData->image().plane(3).at(x, py) : 1.0f;
                    s.instance = instances ? uint32_t(instances->image().plane(0).at(x, py)) : 0u;
                    ++pixels;
                }
                for (int sample = 0; sample < spp; ++sample) {
                    std::array<Ray, kPacketSize> ray{};
                    bool traced[kPacketSize] = {}, blocked[kPacketSize] = {};
                    for (int i = 0; i < kPacketSize; ++i) {
                        PixelSetup& s = px[i];
                        if (!s.active)
                            continue;
                        const float u = rng[i].nextFloat(), v = rng[i].nextFloat();
                        const Vec3f Lc = generator.centreDirection(s.p);
                        const float NoL = dot(s.n, Lc);
                        if (NoL <= 0.0f && cullsBackFacing(s.model, light.type))
                            continue;
                        // Reference §9.2: towards the camera by max(1e-4·distance, bias), then
                        // along the normal by lerp(bias, 0.01 cm, N·L); a transmissive pixel
                        // facing away starts on its back side instead.
                        Vec3f o = s.p + s.toEye * std::max(1e-4f * s.eyeDistance, maxBias);
                        const float nb =
                            maxBias + (minBias - maxBias) * std::clamp(NoL, 0.0f, 1.0f);
                        const bool backSide =
                            mParams.transmission && NoL <= 0.0f &&
                            (hasThicknessTransmission(s.model) || s.model == kSubsurfaceProfile);
                        o += s.n * (backSide ? -nb : nb);
                        const ShadowDirection sd = generator.sample(o, u, v);
                        ray[i] = Ray{o, sd.dir, 0.0f, sd.tfar};
                        traced[i] = true;
                        ++rays;
                    }
                    if (mParams.rayPackets) {
                        rs.occluded8(ray.data(), traced, blocked);
                    } else {
                        for (int i = 0; i < kPacketSize; ++i)
                            blocked[i] = traced[i] && rs.occluded(ray[i].org, ray[i].dir,
                                                                  ray[i].tnear, ray[i].tfar);
                    }
                    float hitT[kPacketSize];
                    std::fill(hitT, hitT + kPacketSize, -1.0f);
                    if (wantDistance) {
                        if (mParams.rayPackets) {
                            rs.closestHit8(ray.data(), blocked, hitT);
                        } else {
                            for (int i = 0; i < kPacketSize; ++i)
                                if (blocked[i]) {
                                    const RayHit h = rs.intersect(ray[i].org, ray[i].dir,
                                                                  ray[i].tnear, ray[i].tfar);
                                    hitT[i] = h.hit ? h.t : -1.0f;
                                }
                        }
                        for (int i = 0; i < kPacketSize; ++i)
                            distanceRays += blocked[i];
                    }
                    for (int i = 0; i < kPacketSize; ++i) {
                        if (!traced[i])
                            continue;
                        PixelSetup& s = px[i];
                        PixelResult& r = res[i];
                        // A subsurface-profile pixel's transmission channel is its encoded
                        // thickness instead (below).
                        const bool profile = mParams.transmission && s.model == kSubsurfaceProfile;
                        if (!blocked[i]) {
                            r.visibility += 1.0f;
                            if (!profile)
                                r.transmission += 1.0f;
                        } else {
                            if (hitT[i] >= 0.0f && (r.closestHit < 0.0f || hitT[i] < r.closestHit))
                                r.closestHit = hitT[i];
                            if (mParams.transmission && hasThicknessTransmission(s.model)) {
                                // Reference §9.3: the inverted ray from the far end finds where
                                // the light enters the pixel's own object.
                                const float far =
                                    std::min(ray[i].tfar, rs.farthestDistance(ray[i].org));
                                const Vec3f start = ray[i].org + ray[i].dir * far;
                                const RayHit h =
                                    rs.intersectInstance(start, -ray[i].dir, 0.0f, far, s.instance);
                                ++transmissionRays;
                                if (h.hit) {
                                    const float thicknessCm = (far - h.t) / cm;
                                    // Hair has density 1 per cm (reference §9.3).
                                    const float T =
                                        s.model == kHair
                                            ? std::clamp(std::exp(-thicknessCm), 0.0f, 1.0f)
                                            : transmittance(s.opacity, thicknessCm);
                                    r.transmission += T;
                                    if (T == 1.0f)
                                        r.visibility += 1.0f;  // promoted to unoccluded
                                }
                            }
                        }
                        if (profile) {
                            // Subsurface profile: the encoded thickness of its own object towards
                            // the light, up to 5 cm (inferred simplification of Unreal's
                            // constant-tracking estimate, reference §9.3).
                            const float reach = kMaxProfileDistanceCm * cm;
                            const Vec3f start = ray[i].org + ray[i].dir * reach;
                            const RayHit h =
                                rs.intersectInstance(start, -ray[i].dir, 0.0f, reach, s.instance);
                            ++transmissionRays;
                            const float thicknessCm =
                                h.hit
                                    ? (reach - h.t) / cm
                                    : (dot(s.n, ray[i].dir) > 0.0f ? 0.0f : kMaxProfileDistanceCm);
                            r.transmission += encodeThickness(thicknessCm);
                        }
                    }
                }
                for (int i = 0; i < kPacketSize && x0 + i < t.x1; ++i) {
                    const int x = x0 + i;
                    const PixelSetup& s = px[i];
                    if (!s.active) {
                        hitOut.at(x, py) = -1.0f;
                        continue;  // shadow, transmission and attenuation stay 0: no light
                    }
                    float visibility = res[i].visibility / float(spp);
                    const float transmission = res[i].transmission / float(spp);
                    if (hasThicknessTransmission(s.model) && mParams.lodTransitionEnd > 0.0f) {
                        // Reference §9.3: far subsurface pixels blend towards transmission.
                        const float span =
                            std::max(mParams.lodTransitionEnd - mParams.lodTransitionStart, 1e-6f);
                        const float f = std::clamp(
                            (s.eyeDistance / cm - mParams.lodTransitionStart) / span, 0.0f, 1.0f);
                        visibility += (transmission - visibility) * f;
                    }
                    shadowOut.at(x, py) = visibility;
                    transmissionOut.at(x, py) = transmission;
                    hitOut.at(x, py) = res[i].closestHit;
                    LightAttenuation::fromShadow(light.type, visibility, transmission)
                        .store(attenuationOut, x, py);
                }
            }
        ctx.addWork("rays", rays);
        ctx.addWork("transmissionRays", transmissionRays);
        ctx.addWork("distanceRays", distanceRays);
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", skipped);
    });
}

}  // namespace fp
