#include "passes/rt_shadows/RTShadowsPass.h"

#include "screenspace/GBuffer.h"
#include "foundation/Random.h"
#include "foundation/RayScene.h"
#include "foundation/ShadingModel.h"
#include "foundation/Tiles.h"
#include "shading/LightAttenuation.h"
#include "shading/NamedLight.h"
#include "framework/PassPorts.h"
#include "passes/rt_shadows/RTShadowsKernel.h"
#include "passes/rt_shadows/ShadowLanes.h"
#include "passes/rt_shadows/ShadowRayGenerator.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace fp {

namespace {

using shadow::kHitDistance;
using shadow::kInstanceId;
using shadow::kLightAttenuation;
using shadow::kShadow;
using shadow::kTransmission;

constexpr uint32_t kSeed = 0x52545348u;    // "RTSH"

// Each light draws its own random numbers, so adding a light leaves the others' shadows alone.
uint32_t lightSeed(const std::string& name) {
    uint32_t h = 2166136261u;  // FNV-1a
    for (unsigned char c : name)
        h = (h ^ c) * 16777619u;
    return kSeed ^ h;
}

// Work counters of one tile.
struct TileWork {
    uint64_t rays = 0, transmissionRays = 0, distanceRays = 0, pixels = 0, skipped = 0;
    // In shadow::Counter's order, for shadow::addWork.
    void report(PassContext& ctx) const {
        uint64_t counts[shadow::kCounterCount] = {};
        counts[shadow::kRays] = rays;
        counts[shadow::kTransmissionRays] = transmissionRays;
        counts[shadow::kDistanceRays] = distanceRays;
        counts[shadow::kPixels] = pixels;
        counts[shadow::kSkipped] = skipped;
        shadow::addWork(ctx, counts);
    }
};

// The output planes of the pass; attenuation is null when nothing reads it.
struct ShadowOutputs {
    Plane& shadow;
    Plane& transmission;
    Plane& hitDistance;
    Image* attenuation;
};

// The scene as shadow::addSample sees it on the Embree path.
struct EmbreeScene {
    const RayScene& rs;
    float farthestDistance(const Vec3f& p) const { return rs.farthestDistance(p); }
    float instanceHit(const Vec3f& org, const Vec3f& dir, float tfar, uint32_t id) const {
        const RayHit h = rs.intersectInstance(org, dir, 0.0f, tfar, id);
        return h.hit ? h.t : -1.0f;
    }
};

// One light's shadow rays over the frame through Embree, a tile row at a time: each pixel's
// set-up, each sample's rays (in SIMD lanes, ShadowLanes.h, or one pixel at a time as the scalar
// reference, RTShadowsKernel.h's setupPixel and sampleRay), their occlusion in Embree packets,
// what a blocked ray adds (transmission through the pixel's own object) and the per-pixel resolve.
class ShadowTracer {
public:
    ShadowTracer(const RTShadowsParams& params, PassContext& ctx, const shadow::FrameSetup& setup)
        : mParams(params),
          mRs(ctx.scene()),
          mSetup(setup),
          mDepth(ctx.input(gbuffer::kDepth)->image().plane(0)),
          mNormal(ctx.input(gbuffer::kNormal)->image()),
          mModels(ctx.input(gbuffer::kShadingModel)->image().plane(0)),
          mOpacity(ctx.input(gbuffer::kCustomData)
                       ? &ctx.input(gbuffer::kCustomData)->image().plane(3)
                       : nullptr),
          mInstances(ctx.input(kInstanceId) ? &ctx.input(kInstanceId)->image().plane(0) : nullptr),
          mWantDistance(ctx.isRequested(kHitDistance)) {}

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
                shadow::setupRow(mSetup.row, in, rows[r]);
            else
                setupRow(in, rows[r]);
            for (int i = 0; i < count; ++i)
                activeCount += rows[r].active[i] != 0;
        }
        work.pixels += uint64_t(activeCount);
        work.skipped += uint64_t(rowCount * count - activeCount);

        std::array<shadow::Sums, shadow::kStripRows * shadow::kRowCapacity> res{};
        shadow::StripRays rays;
        bool blocked[shadow::kStripRayCapacity];
        float hitT[shadow::kStripRayCapacity];
        const RayArrays arrays{rays.ox, rays.oy, rays.oz, rays.dx, rays.dy, rays.dz, rays.tfar};
        for (int sample = 0; sample < mSetup.spp && activeCount > 0; ++sample) {
            rays.count = 0;
            for (int r = 0; r < rowCount; ++r) {
                if (mParams.lanes)
                    shadow::sampleRow(mSetup.row, r, rows[r], rays);
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
                const int r = shadow::ownerRow(owner), i = shadow::ownerIndex(owner);
                const int x = t.x0 + i, y = y0 + r;
                const Ray ray = arrays.at(k);
                work.transmissionRays += uint64_t(shadow::addSample(
                    mSetup.row, EmbreeScene{mRs}, pixelOf(rows[r], i), {ray.org, ray.dir, ray.tfar},
                    blocked[k], hitT[k], mSetup.cm, [&] { return opacityAt(x, y); },
                    [&] { return instanceAt(x, y); }, res[owner]));
            }
        }
        for (int r = 0; r < rowCount; ++r)
            for (int i = 0; i < count; ++i)
                resolvePixel(rows[r], i, res[shadow::ownerOf(r, i)], t.x0 + i, y0 + r, out);
    }

    // Pixel i of a row's set-up, as RTShadowsKernel.h's functions take it.
    static shadow::Pixel pixelOf(const shadow::RowPixels& px, int i) {
        return {{px.px[i], px.py[i], px.pz[i]}, {px.nx[i], px.ny[i], px.nz[i]},
                {px.ex[i], px.ey[i], px.ez[i]}, px.eyeDistance[i], px.model[i], px.rng[i]};
    }

    // The scalar reference of shadow::setupRow: shadow::setupPixel one pixel at a time.
    void setupRow(const shadow::RowInputs& in, shadow::RowPixels& px) const {
        px.x0 = in.x0;
        px.count = in.count;
        for (int i = 0; i < in.count; ++i) {
            shadow::Pixel p;
            px.active[i] = shadow::setupPixel(mSetup.row, in.x0 + i, in.y, in.depth[i], in.model[i],
                                              {in.normalX[i], in.normalY[i], in.normalZ[i]}, p);
            if (px.active[i])
                storePixel(p, px, i);
        }
    }

    // The inverse of pixelOf.
    static void storePixel(const shadow::Pixel& p, shadow::RowPixels& px, int i) {
        px.px[i] = p.p.x;
        px.py[i] = p.p.y;
        px.pz[i] = p.p.z;
        px.nx[i] = p.n.x;
        px.ny[i] = p.n.y;
        px.nz[i] = p.n.z;
        px.ex[i] = p.toEye.x;
        px.ey[i] = p.toEye.y;
        px.ez[i] = p.toEye.z;
        px.eyeDistance[i] = p.eyeDistance;
        px.model[i] = p.model;
        px.rng[i] = p.rng;
    }

    // The scalar reference of shadow::sampleRow: shadow::sampleRay one pixel at a time. A
    // back-facing pixel's ray is culled (occluded without a ray), but its two random numbers are
    // drawn either way, so every sample of a pixel reads the same stream.
    void sampleRow(int stripRow, shadow::RowPixels& px, shadow::StripRays& rays) const {
        for (int i = 0; i < px.count; ++i) {
            if (!px.active[i])
                continue;
            shadow::Pixel p = pixelOf(px, i);
            shadow::ShadowRay ray;
            const bool traced = shadow::sampleRay(mSetup.row, p, ray);
            px.rng[i] = p.rng;
            if (!traced)
                continue;
            const int k = rays.count++;
            rays.ox[k] = ray.org.x;
            rays.oy[k] = ray.org.y;
            rays.oz[k] = ray.org.z;
            rays.dx[k] = ray.dir.x;
            rays.dy[k] = ray.dir.y;
            rays.dz[k] = ray.dir.z;
            rays.tfar[k] = ray.tfar;
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

    // CustomData.A (the subsurface opacity: the transmission density) and the InstanceId of pixel
    // (x, y), read where a transmission ray needs them.
    float opacityAt(int x, int y) const { return mOpacity ? mOpacity->at(x, y) : 1.0f; }
    uint32_t instanceAt(int x, int y) const {
        return mInstances ? shadow::instanceIdOf(mInstances->at(x, y)) : 0u;
    }

    // Pixel i's outputs (shadow::resolve), written with their light-attenuation encoding where it
    // is read.
    void resolvePixel(const shadow::RowPixels& px,
                      int i,
                      const shadow::Sums& r,
                      int x,
                      int py,
                      const ShadowOutputs& out) const {
        if (!px.active[i]) {
            out.hitDistance.at(x, py) = -1.0f;
            return;  // shadow, transmission and attenuation stay 0: no light
        }
        const shadow::Resolved v = shadow::resolve(pixelOf(px, i), r, mSetup);
        out.shadow.at(x, py) = v.visibility;
        out.transmission.at(x, py) = v.transmission;
        out.hitDistance.at(x, py) = r.closestHit;
        if (out.attenuation)
            LightAttenuation::fromShadow(mSetup.row.light.type, v.visibility, v.transmission)
                .store(*out.attenuation, x, py);
    }

    const RTShadowsParams& mParams;
    const RayScene& mRs;
    const shadow::FrameSetup& mSetup;
    const Plane& mDepth;
    const Image& mNormal;
    const Plane& mModels;
    const Plane* mOpacity;    // CustomData.A: subsurface opacity, the transmission density
    const Plane* mInstances;  // the pixel's own object for transmission rays
    const bool mWantDistance;  // closest-hit rays only where a blocked ray's distance is read
};

}  // namespace

namespace shadow {
FrameSetup setupFrame(const RTShadowsParams& params, PassContext& ctx) {
    const RayScene& rs = ctx.scene();
    const Light& light = namedLight(rs.scene().lights, params.light);
    const CameraView& cam = ctx.frame().camera.current;
    FrameSetup s{};
    s.cm = float(rs.scene().centimetre());
    s.spp = params.samplesPerPixel > 0 ? params.samplesPerPixel : light.samplesPerPixel;
    s.lodStart = params.lodTransitionStart;
    s.lodEnd = params.lodTransitionEnd;
    s.row.camera = cam;
    s.row.eyeOffset = cam.position - rs.origin();
    s.row.light = shadowLightShape(light, rs.origin());
    const RayBias bias = RayBias::fromCm(params.normalBias, s.cm);
    s.row.maxBias = bias.max;
    s.row.minBias = bias.min;
    s.row.transmission = params.transmission;
    s.row.rngKey = Rng::frameKey(ctx.frame().number, lightSeed(light.name));
    return s;
}
}  // namespace shadow

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
    s.add("traversal", &Params::traversal,
          "\"embree\": Embree's packets; \"bvh\": framepass's own BVH one pixel at a time, the "
          "code the GPU runs (on the GPU the pass always traverses it)")
        .choices({"embree", "bvh"});
    return s;
}

PassIO RTShadowsPass::describe() const {
    PassIO io;
    io.roles.tracesRays = true;  // bench replays its rays in a bare Embree loop
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

void RTShadowsPass::execute(PassContext& ctx) {
    const shadow::FrameSetup setup = shadow::setupFrame(mParams, ctx);
    if (mParams.traversal == "bvh") {
        shadow::run(ctx, HostPorts{ctx}, CpuPixels{}, setup);
        return;
    }
    const ShadowTracer tracer(mParams, ctx, setup);
    const Extent size = ctx.frame().extent;
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
        work.report(ctx);
    });
}

}  // namespace fp
