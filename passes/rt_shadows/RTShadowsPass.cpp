#include "passes/rt_shadows/RTShadowsPass.h"

#include "screenspace/GBuffer.h"
#include "foundation/Random.h"
#include "foundation/RayScene.h"
#include "foundation/ShadingModel.h"
#include "foundation/Tiles.h"
#include "shading/LightAttenuation.h"
#include "shading/NamedLight.h"
#include "passes/rt_shadows/ShadowLanes.h"
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
constexpr float kMinNormalBiasCm = 0.01f;  // algorithms §9.1: r.RayTracing.NormalBias min 0.01

// Each light draws its own random numbers, so adding a light leaves the others' shadows alone.
uint32_t lightSeed(const std::string& name) {
    uint32_t h = 2166136261u;  // FNV-1a
    for (unsigned char c : name)
        h = (h ^ c) * 16777619u;
    return kSeed ^ h;
}

// algorithms §9.2: N·L ≤ 0 means "occluded" without a ray, except for hair, eye, two-sided foliage,
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

struct PixelResult {
    float visibility = 0, transmission = 0, closestHit = -1;
};

// Work counters of one tile.
struct TileWork {
    uint64_t rays = 0, transmissionRays = 0, distanceRays = 0, pixels = 0, skipped = 0;
};

// The output planes of the pass; attenuation is null when nothing reads it.
struct ShadowOutputs {
    Plane& shadow;
    Plane& transmission;
    Plane& hitDistance;
    Image* attenuation;
};

// One light's shadow rays over the frame, a tile row at a time: each pixel's set-up, each
// sample's rays (in SIMD lanes, ShadowLanes.h, or one pixel at a time as the scalar reference),
// their occlusion in Embree packets, what a blocked ray adds (transmission through the pixel's
// own object) and the per-pixel resolve.
class ShadowTracer {
public:
    ShadowTracer(const RTShadowsParams& params,
                 PassContext& ctx,
                 const RayScene& rs,
                 const Light& light)
        : mParams(params),
          mRs(rs),
          mLight(light),
          mGenerator(light, rs.origin()),
          mCm(float(rs.scene().centimetre())),
          mSpp(params.samplesPerPixel > 0 ? params.samplesPerPixel : light.samplesPerPixel),
          mDepth(ctx.input(gbuffer::kDepth)->image().plane(0)),
          mNormal(ctx.input(gbuffer::kNormal)->image()),
          mModels(ctx.input(gbuffer::kShadingModel)->image().plane(0)),
          mOpacity(ctx.input(gbuffer::kCustomData)
                       ? &ctx.input(gbuffer::kCustomData)->image().plane(3)
                       : nullptr),
          mInstances(ctx.input(kInstanceId) ? &ctx.input(kInstanceId)->image().plane(0) : nullptr),
          mWantDistance(ctx.isRequested(kHitDistance)) {
        const CameraView& cam = ctx.frame().camera.current;
        mRow.camera = &cam;
        mRow.eyeOffset = cam.position - rs.origin();
        mRow.light = mGenerator.shape();
        mRow.maxBias = std::max(params.normalBias, kMinNormalBiasCm) * mCm;
        mRow.minBias = kMinNormalBiasCm * mCm;
        mRow.transmission = params.transmission;
        mRow.rngKey = Rng::frameKey(ctx.frame().number, lightSeed(light.name));
    }

    /// The tile's pixels, kStripRows rows at a time. Each sample's rays of a strip are gathered
    /// from the pixels that trace one (unlit, sky, unreachable and back-facing pixels trace none)
    /// and traced in full packets of RayScene::packetWidth() (16 with AVX-512, else 8), as the
    /// bare Embree loop traces them: a packet of neighbouring pixels, most of them idle at a
    /// shadow's or the light's edge, would cost a full packet's traversal, and so would a row's
    /// last, part-filled packet. Every pixel still draws its own random stream and adds its
    /// samples in sample order, so the result is that of one ray at a time.
    void traceTile(const Tile& t, const ShadowOutputs& out, TileWork& work) const {
        for (int y0 = t.y0; y0 < t.y1; y0 += shadow::kStripRows)
            traceStrip(t, y0, std::min(y0 + shadow::kStripRows, t.y1), out, work);
    }

private:
    // Rows [y0, y1) of tile t. The strip's working set (about 130 KB: its rows' set-up, one
    // sample's rays and the running sums) lives on the stack; TBB's workers have megabytes.
    void traceStrip(const Tile& t, int y0, int y1, const ShadowOutputs& out, TileWork& work) const {
        const int rowCount = y1 - y0, count = t.x1 - t.x0;
        std::array<shadow::RowPixels, shadow::kStripRows> rows;
        int activeCount = 0;
        for (int r = 0; r < rowCount; ++r) {
            const int py = y0 + r;
            const shadow::RowInputs in{.x0 = t.x0,
                                       .y = py,
                                       .count = count,
                                       .depth = mDepth.row(py) + t.x0,
                                       .normalX = mNormal.plane(0).row(py) + t.x0,
                                       .normalY = mNormal.plane(1).row(py) + t.x0,
                                       .normalZ = mNormal.plane(2).row(py) + t.x0,
                                       .model = mModels.row(py) + t.x0};
            if (mParams.lanes)
                shadow::setupRow(mRow, in, rows[r]);
            else
                setupRow(in, rows[r]);
            for (int i = 0; i < count; ++i)
                activeCount += rows[r].active[i] != 0;
        }
        work.pixels += uint64_t(activeCount);
        work.skipped += uint64_t(rowCount * count - activeCount);

        std::array<PixelResult, shadow::kStripRows * shadow::kRowCapacity> res{};
        shadow::StripRays rays;
        bool blocked[shadow::kStripRayCapacity];
        float hitT[shadow::kStripRayCapacity];
        const RayArrays arrays{rays.ox, rays.oy, rays.oz, rays.dx, rays.dy, rays.dz, rays.tfar};
        for (int sample = 0; sample < mSpp && activeCount > 0; ++sample) {
            rays.count = 0;
            for (int r = 0; r < rowCount; ++r) {
                if (mParams.lanes)
                    shadow::sampleRow(mRow, r, rows[r], rays);
                else
                    sampleRow(r, rows[r], rays);
            }
            work.rays += uint64_t(rays.count);
            const int width = mRs.packetWidth();
            for (int first = 0; first < rays.count; first += width)
                trace(arrays.from(first), std::min(width, rays.count - first), &blocked[first],
                      &hitT[first], work);
            for (int k = 0; k < rays.count; ++k) {
                const int32_t owner = rays.owner[k];
                const int r = shadow::ownerRow(owner);
                addSample(rows[r], shadow::ownerIndex(owner), y0 + r, arrays.at(k), blocked[k],
                          hitT[k], res[owner], work);
            }
        }
        for (int r = 0; r < rowCount; ++r)
            for (int i = 0; i < count; ++i)
                resolvePixel(rows[r], i, res[shadow::ownerOf(r, i)], t.x0 + i, y0 + r, out);
    }

    // The scalar reference of shadow::setupRow: what stays the same for all samples of each
    // pixel; inactive for unlit and sky pixels and those the light cannot reach.
    void setupRow(const shadow::RowInputs& in, shadow::RowPixels& px) const {
        px.x0 = in.x0;
        px.count = in.count;
        const CameraView& cam = *mRow.camera;
        for (int i = 0; i < in.count; ++i) {
            px.active[i] = 0;
            const double d = in.depth[i];
            const float model = in.model[i];
            if (!isLitSurface(d, model))
                continue;  // sky and unlit pixels: nothing to rebuild
            const int x = in.x0 + i;
            const Vec3d offset = cam.translatedFromPixel(x, in.y, d);
            const Vec3f p(mRow.eyeOffset + offset);
            if (!mGenerator.reaches(p))
                continue;
            px.active[i] = 1;
            px.px[i] = p.x;
            px.py[i] = p.y;
            px.pz[i] = p.z;
            const double eyeDistance = length(offset);
            px.eyeDistance[i] = float(eyeDistance);
            const Vec3f toEye(-offset / eyeDistance);
            px.ex[i] = toEye.x;
            px.ey[i] = toEye.y;
            px.ez[i] = toEye.z;
            px.model[i] = truncToInt(model, 0, 255);
            // Hair's GBuffer normal is its tangent: Unreal biases along the light instead.
            const Vec3f n = px.model[i] == kHair
                                ? mGenerator.centreDirection(p)
                                : Vec3f{in.normalX[i], in.normalY[i], in.normalZ[i]};
            px.nx[i] = n.x;
            px.ny[i] = n.y;
            px.nz[i] = n.z;
            px.rng[i] = Rng::fromKey(mRow.rngKey, x, in.y).state();  // per-pixel streams
        }
    }

    // The scalar reference of shadow::sampleRow: one sample's rays of the active pixels. A
    // back-facing pixel's ray is culled (occluded without a ray), but its two random numbers are
    // drawn either way, so every sample of a pixel reads the same stream.
    void sampleRow(int stripRow, shadow::RowPixels& px, shadow::StripRays& rays) const {
        for (int i = 0; i < px.count; ++i) {
            if (!px.active[i])
                continue;
            Rng rng = Rng::resume(px.rng[i]);
            const float u = rng.nextFloat(), v = rng.nextFloat();
            px.rng[i] = rng.state();
            const Vec3f p{px.px[i], px.py[i], px.pz[i]}, n{px.nx[i], px.ny[i], px.nz[i]};
            const int model = px.model[i];
            const float NoL = dot(n, mGenerator.centreDirection(p));
            if (NoL <= 0.0f && cullsBackFacing(model, mLight.type))
                continue;
            // algorithms §9.2: towards the camera by max(1e-4·distance, bias), then along the
            // normal by lerp(bias, 0.01 cm, N·L); a transmissive pixel facing away starts on its
            // back side instead.
            const Vec3f toEye{px.ex[i], px.ey[i], px.ez[i]};
            Vec3f o = p + toEye * std::max(1e-4f * px.eyeDistance[i], mRow.maxBias);
            const float nb =
                mRow.maxBias + (mRow.minBias - mRow.maxBias) * std::clamp(NoL, 0.0f, 1.0f);
            const bool backSide = mParams.transmission && NoL <= 0.0f &&
                                  (hasThicknessTransmission(model) || model == kSubsurfaceProfile);
            o += n * (backSide ? -nb : nb);
            const ShadowDirection sd = mGenerator.sample(o, u, v);
            const int k = rays.count++;
            rays.ox[k] = o.x;
            rays.oy[k] = o.y;
            rays.oz[k] = o.z;
            rays.dx[k] = sd.dir.x;
            rays.dy[k] = sd.dir.y;
            rays.dz[k] = sd.dir.z;
            rays.tfar[k] = sd.tfar;
            rays.owner[k] = shadow::ownerOf(stripRow, i);
        }
    }

    // Occlusion of the first `count` (1 to the packet width) of the rays, and where a blocked ray's
    // distance is wanted (the denoiser's input) its closest hit (−1: none), asked for the blocked
    // rays only; as a packet or one ray at a time, with the same result.
    void trace(const RayArrays& rays, int count, bool blocked[], float hitT[],
               TileWork& work) const {
        if (mParams.rayPackets) {
            mRs.occludedWithDistancePacket(rays, count, mRs.packetWidth(), blocked,
                                           mWantDistance ? hitT : nullptr);
            if (!mWantDistance)
                std::fill(hitT, hitT + count, -1.0f);
        } else {
            for (int i = 0; i < count; ++i) {
                const Ray r = rays.at(i);
                blocked[i] = mRs.occluded(r.org, r.dir, 0.0f, r.tfar);
                hitT[i] = -1.0f;
                if (mWantDistance && blocked[i]) {
                    const RayHit h = mRs.intersect(r.org, r.dir, 0.0f, r.tfar);
                    hitT[i] = h.hit ? h.t : -1.0f;
                }
            }
        }
        if (mWantDistance)
            for (int i = 0; i < count; ++i)
                work.distanceRays += blocked[i];
    }

    // What one traced sample of pixel i of row py adds to it.
    void addSample(const shadow::RowPixels& px,
                   int i,
                   int py,
                   const Ray& ray,
                   bool blocked,
                   float hitT,
                   PixelResult& r,
                   TileWork& work) const {
        const int model = px.model[i];
        // A subsurface-profile pixel's transmission channel is its encoded thickness instead.
        const bool profile = mParams.transmission && model == kSubsurfaceProfile;
        if (!blocked) {
            r.visibility += 1.0f;
            if (!profile)
                r.transmission += 1.0f;
        } else {
            if (hitT >= 0.0f && (r.closestHit < 0.0f || hitT < r.closestHit))
                r.closestHit = hitT;
            if (mParams.transmission && hasThicknessTransmission(model))
                addThicknessTransmission(px.model[i], opacityAt(px.x0 + i, py),
                                         instanceAt(px.x0 + i, py), ray, r, work);
        }
        if (profile)
            r.transmission += profileThickness(px, i, instanceAt(px.x0 + i, py), ray, work);
    }

    // algorithms §9.3: the inverted ray from the far end finds where the light enters the pixel's
    // own object; the thickness gives the transmittance (hair: density 1 per cm), and a fully
    // transmitted sample counts as unoccluded.
    void addThicknessTransmission(int model,
                                  float opacity,
                                  uint32_t instance,
                                  const Ray& ray,
                                  PixelResult& r,
                                  TileWork& work) const {
        const float far = std::min(ray.tfar, mRs.farthestDistance(ray.org));
        const Vec3f start = ray.org + ray.dir * far;
        const RayHit h = mRs.intersectInstance(start, -ray.dir, 0.0f, far, instance);
        ++work.transmissionRays;
        if (!h.hit)
            return;
        const float thicknessCm = (far - h.t) / mCm;
        const float T = model == kHair ? std::clamp(std::exp(-thicknessCm), 0.0f, 1.0f)
                                       : RTShadowsPass::transmittance(opacity, thicknessCm);
        r.transmission += T;
        if (T == 1.0f)
            r.visibility += 1.0f;  // promoted to unoccluded
    }

    // Subsurface profile: the encoded thickness of its own object towards the light, up to 5 cm
    // (inferred simplification of Unreal's constant-tracking estimate, algorithms §9.3).
    float profileThickness(const shadow::RowPixels& px,
                           int i,
                           uint32_t instance,
                           const Ray& ray,
                           TileWork& work) const {
        const float reach = RTShadowsPass::kMaxProfileDistanceCm * mCm;
        const Vec3f start = ray.org + ray.dir * reach;
        const RayHit h = mRs.intersectInstance(start, -ray.dir, 0.0f, reach, instance);
        ++work.transmissionRays;
        const Vec3f n{px.nx[i], px.ny[i], px.nz[i]};
        const float thicknessCm =
            h.hit ? (reach - h.t) / mCm
                  : (dot(n, ray.dir) > 0.0f ? 0.0f : RTShadowsPass::kMaxProfileDistanceCm);
        return RTShadowsPass::encodeThickness(thicknessCm);
    }

    // CustomData.A (the subsurface opacity: the transmission density) and the InstanceId of pixel
    // (x, y), read where a transmission ray needs them.
    float opacityAt(int x, int y) const { return mOpacity ? mOpacity->at(x, y) : 1.0f; }
    uint32_t instanceAt(int x, int y) const {
        return mInstances ? uint32_t(truncToInt(mInstances->at(x, y), 0, 1 << 30)) : 0u;
    }

    // Pixel i's means over its samples, with far subsurface pixels blended towards transmission
    // (algorithms §9.3), written with their light-attenuation encoding where it is read.
    void resolvePixel(const shadow::RowPixels& px,
                      int i,
                      const PixelResult& r,
                      int x,
                      int py,
                      const ShadowOutputs& out) const {
        if (!px.active[i]) {
            out.hitDistance.at(x, py) = -1.0f;
            return;  // shadow, transmission and attenuation stay 0: no light
        }
        float visibility = r.visibility / float(mSpp);
        const float transmission = r.transmission / float(mSpp);
        if (hasThicknessTransmission(px.model[i]) && mParams.lodTransitionEnd > 0.0f) {
            const float span =
                std::max(mParams.lodTransitionEnd - mParams.lodTransitionStart, 1e-6f);
            const float f = std::clamp(
                (px.eyeDistance[i] / mCm - mParams.lodTransitionStart) / span, 0.0f, 1.0f);
            visibility += (transmission - visibility) * f;
        }
        out.shadow.at(x, py) = visibility;
        out.transmission.at(x, py) = transmission;
        out.hitDistance.at(x, py) = r.closestHit;
        if (out.attenuation)
            LightAttenuation::fromShadow(mLight.type, visibility, transmission)
                .store(*out.attenuation, x, py);
    }

    const RTShadowsParams& mParams;
    const RayScene& mRs;
    const Light& mLight;
    const ShadowRayGenerator mGenerator;
    const float mCm;
    const int mSpp;
    const Plane& mDepth;
    const Image& mNormal;
    const Plane& mModels;
    const Plane* mOpacity;    // CustomData.A: subsurface opacity, the transmission density
    const Plane* mInstances;  // the pixel's own object for transmission rays
    const bool mWantDistance;  // closest-hit rays only where a blocked ray's distance is read
    shadow::RowContext mRow;   // the camera, light and biases both set-ups and samplers read
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
          "trace Embree packets of neighbouring pixels' rays, rtcOccluded16 with AVX-512 and "
          "rtcOccluded8 elsewhere (false: one ray at a time; same result bit for bit)");
    s.add("lanes", &Params::lanes,
          "set up pixels and draw their rays in SIMD lanes (false: the scalar reference, one pixel "
          "at a time; same result bit for bit)");
    return s;
}

PassIO RTShadowsPass::describe() const {
    PassIO io;
    io.roles.tracesShadowRays = true;  // bench replays its rays in a bare Embree loop
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
         .doc = "Unreal's light-attenuation encoding (algorithms §9.5), √ of the faded shadow"},
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
    // Unreal's light-attenuation encoding is only written where a reader asks for it (the lit
    // chain's denoiser and deferred lighting read shadow, transmission and hitDistance).
    const ShadowOutputs out{
        ctx.output(kShadow, {size}).image().plane(0),
        ctx.output(kTransmission, {size}).image().plane(0),
        ctx.output(kHitDistance, {size}).image().plane(0),
        ctx.isRequested(kLightAttenuation) ? &ctx.output(kLightAttenuation, {size}).image()
                                           : nullptr};
    forEachTile(size.width, size.height, [&](const Tile& t) {
        TileWork work;
        tracer.traceTile(t, out, work);
        ctx.addWork("rays", work.rays);
        ctx.addWork("transmissionRays", work.transmissionRays);
        ctx.addWork("distanceRays", work.distanceRays);
        ctx.addWork("pixels", work.pixels);
        ctx.addWork("skippedPixels", work.skipped);
    });
}

}  // namespace fp
