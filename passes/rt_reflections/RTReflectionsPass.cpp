#include "passes/rt_reflections/RTReflectionsPass.h"

#include "foundation/Environment.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/Random.h"
#include "foundation/RayScene.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "foundation/Tiles.h"
#include "framework/PassPorts.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Surface.h"
#include "screenspace/TraceResolution.h"
#include "shading/DirectLighting.h"
#include "shading/RayOriginBias.h"
#include "passes/rt_reflections/RTReflectionsKernel.h"
#include "passes/rt_reflections/RTReflectionsLanes.h"
#include "shading/ReflectionHitWave.h"
#include "shading/ReflectionHits.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace fp {

namespace {

using rtr::kHitDistance;
using rtr::kReflection;
using rtr::kSceneColor;
constexpr uint32_t kSeed = 0x52545246u;  // "RTRF"

/// What a wave of a tile's texels holds (RTReflectionsPass::traceWaves).
struct WaveArrays {
    std::vector<rtr::Texel> texels;  // the tile's texels that trace
    std::vector<int> at;             // and where each is in the tile
    std::array<int, kTileSize + 16> tracing;  // a row's texels that trace (room for a vector more)
    std::vector<Ray> packet;  // the texels' rays this step
    std::vector<RayHit> rayHits;
    std::vector<PathHit> hits;
    std::vector<const SurfacePoint*> lit;  // the hits left to be lit
    std::vector<Rng*> rngs;
    std::vector<std::size_t> litOwner;
    std::vector<Vec3f> radiance;
    rtr::TexelLanes lanes;  // the texels as the lanes that draw their rays read them
    ReflectionHitWave wave;
};

}  // namespace

ParamSpec<RTReflectionsParams> RTReflectionsPass::paramSpec() {
    ParamSpec<RTReflectionsParams> s;
    s.add("samplesPerPixel", &Params::samplesPerPixel,
          "reflection rays per pixel; −1 = the post-process volume's RayTracingReflectionsSamplesPerPixel (1)")
        .range(-1, 256)
        .cvar("r.RayTracing.Reflections.SamplesPerPixel");
    s.add("maxRoughness", &Params::maxRoughness,
          "rougher pixels trace nothing (faded from half of it); −1 = the post-process volume's "
          "RayTracingReflectionsMaxRoughness (0.6)")
        .range(-1.0, 1.0)
        .cvar("r.RayTracing.Reflections.MaxRoughness");
    s.add("shadows", &Params::shadows,
          "shadow rays at hits: 0 off (every light unshadowed), 1 hard, 2 soft (framepass samples "
          "the light's area for both); −1 = the post-process volume's hard")
        .range(-1, 2)
        .cvar("r.RayTracing.Reflections.Shadows");
    s.add("normalBias", &Params::normalBias, "the reflection ray's origin bias, cm")
        .range(0.01, 1e6)
        .cvar("r.RayTracing.Reflections.NormalBias");
    s.add("hybrid", &Params::hybrid,
          "Unreal's hybrid: a hit that projects on screen less than 5 cm behind the depth buffer "
          "takes `sceneColor` there (this frame's lit colour) instead of being shaded, and shaded "
          "hits take the camera's view vector")
        .cvar("r.RayTracing.Reflections.Hybrid");
    s.add("screenPercentage", &Params::screenPercentage,
          "traces one pixel of each k×k block, k = int(100 / this) (reflection_denoise upscales); "
          "100, Unreal's default, traces every pixel")
        .range(25.0, 100.0)
        .cvar("r.RayTracing.Reflections.ScreenPercentage");
    s.add("hitIndirectBounces", &Params::hitIndirectBounces,
          "a hit's diffuse indirect light: 0 (Unreal's) the sky light's SH irradiance, unshadowed; "
          "n > 0 (framepass's) traced from the hit by one cosine path of n bounces, which sees "
          "the sky only through the scene's openings and other surfaces lit by the lights")
        .range(0, 16);
    s.add("traversal", &Params::traversal,
          "\"embree\": Embree's scene; \"bvh\": framepass's own BVH, the code the GPU runs (on "
          "the GPU the pass always traverses it; a hit's traced indirect light, "
          "hitIndirectBounces > 0, keeps the pass on the CPU under a sky light, and \"bvh\" is "
          "refused there)")
        .choices({"embree", "bvh"});
    s.add("waves", &Params::waves,
          "with Embree, a tile's reflection rays traced together: drawn in SIMD lanes, their "
          "closest hits in Embree's packets, their hits' light samples in lanes and their shadow "
          "rays in packets (false: each ray and its shadow rays one at a time; the same bits)");
    return s;
}

std::vector<Extent> RTReflectionsPass::outputExtents(std::string_view, Extent frame) const {
    return {traceExtent(frame, screenPercentageUpscale(mParams.screenPercentage))};
}

PassIO RTReflectionsPass::describe() const {
    PassIO io;
    io.roles.unrealSwitch = "r.RayTracing.Reflections=1";
    io.roles.tracesRays = true;  // bench replays its rays in bare Embree loops
    io.inputs = {
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit, hair and sky pixels are skipped"),
        gbuffer::roughnessInput("the GGX lobe the ray is drawn from, and the cutoff"),
    };
    if (mParams.hybrid)
        io.inputs.push_back(gbuffer::sceneColorInput(
            kSceneColor, "hybrid: this frame's lit colour, read where a hit lands on screen"));
    io.outputs = {
        {.name = kReflection,
         .channels = {"R", "G", "B", "A"},
         .kind = PortKind::Color,
         .doc = "pre-BRDF reflected radiance × the roughness fade, coverage (the fade) in A: "
                "what ssr.reflection holds, for reflection_environment"},
        {.name = kHitDistance,
         .channels = {"Y"},
         .doc = "mean distance to the rays' hits, scene units; 1e20 where only the sky was seen, "
                "−1 no ray hit, −2 skipped"},
    };
    io.needsCamera = true;
    io.needsScene = true;
    io.workUnit = "rays";
    return io;
}

rtr::FrameSetup RTReflectionsPass::frameSetup(PassContext& ctx) {
    const RayScene& rs = ctx.scene();
    mSky = ReflectedSky::of(rs.scene().environment.sky, mSky);
    const CameraView& cam = ctx.frame().camera.current;
    const float cm = float(rs.scene().centimetre());
    rtr::FrameSetup s{};
    s.camera = cam;
    s.eyeOffset = cam.position - rs.origin();
    s.origin = rs.origin();
    s.frame = ctx.frame().extent;
    s.upscale = screenPercentageUpscale(mParams.screenPercentage);
    s.spp = mParams.samplesPerPixel > 0 ? mParams.samplesPerPixel : 1;
    s.maxRoughness =
        std::clamp(mParams.maxRoughness < 0.0f ? 0.6f : mParams.maxRoughness, 0.01f, 1.0f);
    s.bias = RayBias::fromCm(mParams.normalBias, cm);
    s.hybridDepth = rtr::kHybridDepthCm * cm;
    s.shadowed = mParams.shadows != 0;
    s.lightSamples = 1;  // DirectLighting(rs, 1): one sample a light
    s.indirectBounces = mParams.hitIndirectBounces;
    s.rngKey = Rng::frameKey(ctx.frame().number, kSeed);
    return s;
}

void RTReflectionsPass::execute(PassContext& ctx) {
    const rtr::FrameSetup setup = frameSetup(ctx);
    const Extent trace = outputExtents(kReflection, ctx.frame().extent).front();
    const RayScene& rs = ctx.scene();
    const DirectLighting lighting(rs, setup.lightSamples);
    std::shared_ptr<const Vec3f> cubeTexels;
    const rtr::Sky sky = rtr::skyFor(HostPorts{ctx}, mSky.get(), cubeTexels);
    if (mParams.traversal == "bvh") {
        if (mSky && mParams.hitIndirectBounces > 0)
            throw UsageError("rt_reflections: traversal \"bvh\" reads no sky along a hit's "
                             "indirect path, and hitIndirectBounces asks for one under the scene's "
                             "sky light: use traversal \"embree\"");
        std::shared_ptr<const LightView> lights;
        rtr::run(ctx, HostPorts{ctx}, CpuPixels{}, setup, sky, trace,
                 bvhTracerFor(HostPorts{ctx}, lighting, lights), mParams.hybrid, "rt_reflections");
        return;
    }
    if (!mParams.waves) {
        DiffusePathSetup paths;
        paths.scene = &rs;
        paths.lighting = &lighting;
        paths.sky = mSky ? mSky->source : nullptr;
        rtr::run(ctx, HostPorts{ctx}, CpuPixels{}, setup, sky, trace, EmbreeTracer{paths},
                 mParams.hybrid, "rt_reflections");
        return;
    }
    traceWaves(ctx, setup, rtr::frameOf(HostPorts{ctx}, setup, sky, trace, mParams.hybrid), trace,
               lighting);
}

void RTReflectionsPass::traceWaves(PassContext& ctx, const rtr::FrameSetup& setup,
                                   const rtr::Frame& f, Extent trace,
                                   const DirectLighting& lighting) {
    const RayScene& rs = ctx.scene();
    const ReflectionHitLighting how{&rs, &lighting, mSky.get(), setup.shadowed,
                                    setup.indirectBounces};
    DiffusePathSetup paths;
    paths.scene = &rs;
    paths.lighting = &lighting;
    const EmbreeTracer tracer{paths};  // fills the hits' shading points
    const int width = rs.packetWidth();
    forEachTile(trace.width, trace.height, [&](const Tile& t) {
        // A tile at a time: every texel set up, then the k-th rays of those that trace traced
        // together, k = 0, 1, …: each texel's stream draws its rays (and their hits' samples)
        // in order, as reflectionTexel's loop does.
        WorkCounts<rtr::kCounterCount> counts{};
        // Each worker's arrays, kept from tile to tile: a tile's are some 2 MB, which fresh
        // allocations would take from the kernel page by page every tile.
        thread_local WaveArrays a;
        auto& [texels, at, tracing, packet, rayHits, hits, lit, rngs, litOwner, radiance, lanes,
               wave] = a;
        texels.clear();
        at.clear();
        for (int y = t.y0; y < t.y1; ++y) {
            // The GBuffer reads of two rows ahead started now: a tile's rows lie a frame's width
            // apart, in pages where the hardware's prefetcher starts afresh, and a row of pixels
            // that trace nothing is only these reads and the writes of its skipped values.
            if (y + 2 < t.y1) {
                const PixelCoord p0 = fullResPixel(t.x0, y + 2, setup.upscale, setup.frame.width,
                                                   setup.frame.height);
                const PixelCoord p1 = fullResPixel(t.x1 - 1, y + 2, setup.upscale,
                                                   setup.frame.width, setup.frame.height);
                for (const PlaneView* plane : {&f.depth, &f.model, &f.roughness})
                    for (int x = p0.x; x <= p1.x; x += 16)
                        __builtin_prefetch(plane->data + planeIndex(x, p0.y, plane->stride));
                for (const PlaneSpan* plane : {&f.reflection[0], &f.reflection[1], &f.reflection[2],
                                               &f.reflection[3], &f.hitDistance})
                    for (int x = t.x0; x < t.x1; x += 16)
                        __builtin_prefetch(plane->data + planeIndex(x, y + 2, plane->stride), 1);
            }
            // Most texels trace nothing (too rough, or sky): the row is written as skipped in
            // one sweep, the texels that trace are told apart by the predicate alone (a vector
            // of the row's pixels at a time where texel and pixel are one) and set up, their
            // values written over the skipped ones at the tile's end.
            for (int x = t.x0; x < t.x1; ++x) rtr::writeSkipped(f, x, y);
            int n = 0;
            if (setup.upscale == 1) {
                n = rtr::tracingTexelsOfRow(f, y, t.x0, t.x1, tracing.data());
            } else {
                for (int x = t.x0; x < t.x1; ++x)
                    if (rtr::tracesAt(f, fullResPixel(x, y, setup.upscale, setup.frame.width,
                                                      setup.frame.height)))
                        tracing[std::size_t(n++)] = x;
            }
            for (int i = 0; i < n; ++i) {
                const int x = tracing[std::size_t(i)];
                texels.push_back(rtr::tracedTexelAt(
                    f, fullResPixel(x, y, setup.upscale, setup.frame.width, setup.frame.height)));
                at.push_back((y - t.y0) * kTileSize + (x - t.x0));
            }
        }
        counts.value[rtr::kSkipped] += uint64_t((t.x1 - t.x0) * (t.y1 - t.y0)) - texels.size();
        const std::size_t going = texels.size();
        packet.resize(going);
        rayHits.resize(going);
        hits.resize(going);
        ReflectionHitWork work;
        lanes.resize(int(going));
        for (std::size_t i = 0; i < going; ++i) {
            const rtr::Texel& texel = texels[i];
            lanes.px[i] = texel.surface.p.x;
            lanes.py[i] = texel.surface.p.y;
            lanes.pz[i] = texel.surface.p.z;
            lanes.ex[i] = texel.surface.toEye.x;
            lanes.ey[i] = texel.surface.toEye.y;
            lanes.ez[i] = texel.surface.toEye.z;
            lanes.distance[i] = texel.surface.eyeDistance;
            lanes.nx[i] = texel.N.x;
            lanes.ny[i] = texel.N.y;
            lanes.nz[i] = texel.N.z;
            lanes.roughness[i] = texel.roughness;
        }
        for (int k = 0; k < setup.spp; ++k) {
            // The texels' rays in SIMD lanes, each from its own stream.
            for (std::size_t i = 0; i < going; ++i) lanes.rng[i] = texels[i].rng.state();
            rtr::drawTexelRayLanes(setup.bias, lanes);
            for (std::size_t i = 0; i < going; ++i) {
                texels[i].rng = Rng::resume(lanes.rng[i]);
                packet[i] = {{lanes.ox[i], lanes.oy[i], lanes.oz[i]},
                             {lanes.lx[i], lanes.ly[i], lanes.lz[i]},
                             0.0f,
                             std::numeric_limits<float>::infinity()};
            }
            for (std::size_t r = 0; r < going; r += std::size_t(width))
                rs.intersectPacket(packet.data() + r, int(std::min(going - r, std::size_t(width))),
                                   width, rayHits.data() + r);
            lit.clear();
            rngs.clear();
            litOwner.clear();
            for (std::size_t i = 0; i < going; ++i) {
                const rtr::ReflectionRay ray{packet[i].org, packet[i].dir};
                tracer.fillPathHit(rayHits[i], ray.org, ray.L, hits[i]);
                if (!rtr::reachHit(f, texels[i], ray, hits[i])) continue;
                rtr::seenFrom(f, ray, hits[i]);
                lit.push_back(&hits[i].surface);
                rngs.push_back(&texels[i].rng);
                litOwner.push_back(i);
            }
            radiance.resize(lit.size());
            wave.light(how, lit.data(), rngs.data(), int(lit.size()), radiance.data(), work);
            for (std::size_t j = 0; j < lit.size(); ++j) texels[litOwner[j]].sum += radiance[j];
        }
        for (std::size_t i = 0; i < going; ++i)
            rtr::writeTexel(f, texels[i], t.x0 + at[i] % kTileSize, t.y0 + at[i] / kTileSize,
                            counts);
        counts.value[rtr::kShadowRays] += work.shadowRays;
        counts.value[rtr::kIndirectRays] += work.indirectRays;
        std::array<uint64_t, rtr::kCounterCount> totals{};
        for (int i = 0; i < rtr::kCounterCount; ++i) totals[std::size_t(i)] = counts.value[i];
        rtr::addWork(ctx, totals, setup, mParams.hybrid);
    });
}

}  // namespace fp
