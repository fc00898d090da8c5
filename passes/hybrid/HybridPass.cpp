#include "passes/hybrid/HybridPass.h"

#include "foundation/PerPixel.h"
#include "foundation/Tiles.h"
#include "framework/PassPorts.h"
#include "passes/hybrid/HybridKernel.h"
#include "passes/hybrid/HybridMarch.h"
#include "passes/ssgi/SSGIKernel.h"
#include "passes/ssgi/SSGIPass.h"
#include "screenspace/GBuffer.h"
#include "shading/DiffusePathWave.h"
#include "shading/DiffusePaths.h"
#include "shading/RayOriginBias.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <vector>

namespace fp {

namespace {

constexpr uint32_t kSeed = 0x48594252u;        // "HYBR"
constexpr uint32_t kOnwardSeed = 0x4F4E5744u;  // "ONWD"

}  // namespace

ParamSpec<HybridParams> HybridPass::paramSpec() {
    ParamSpec<HybridParams> s;
    s.add("quality", &Params::quality,
          "1..4 → SSGI's 4/8/16/32 rays per pixel and 8/8/8/12 steps per ray (algorithms §4.2)")
        .range(1, 4)
        .cvar("r.SSGI.Quality");
    s.add("rays", &Params::rays, "rays per pixel in place of the quality's count (0: the quality's)")
        .range(0, SSGIPass::kMaxRays);
    s.add("maxBounces", &Params::maxBounces,
          "hits a fallback path shades: 1 is the one bounce the screen gives, more add the "
          "light that bounced again")
        .range(1, 64);
    s.add("nextEventEstimationSamples", &Params::nextEventEstimationSamples,
          "light samples (one light picked uniformly, one shadow ray) at each fallback hit")
        .range(0, 64);
    s.add("continueOnScreen", &Params::continueOnScreen,
          "an on-screen hit keeps last frame's colour there and continues as a scene path for "
          "maxBounces − 1 more bounces, from the hit pixel's surface: for captures whose colour "
          "holds direct light only (framepass's own, the blender-direct profile's), where the "
          "screen gives one bounce; off when last frame's colour already holds GI (an engine's, "
          "the blender profile's Cycles Combined), which it would count twice");
    s.add("normalBias", &Params::normalBias,
          "largest normal/camera bias of a fallback ray's origin, cm (at N·L = 0)")
        .range(0.01, 1e6);
    s.add("traversal", &Params::traversal,
          "the scene paths' \"embree\": Embree's scene; \"bvh\": framepass's own BVH, the "
          "code the GPU runs (on the GPU the pass always traverses it)")
        .choices({"embree", "bvh"});
    s.add("waves", &Params::waves,
          "with Embree, a tile's scene paths traced together a step at a time, each step's rays "
          "in Embree's packets and its light samples in SIMD lanes, after SSGI's march has "
          "found which rays fall back, and the march then resolved with what they brought "
          "(false: each path traced when the march falls back, one ray at a time; the same "
          "bits)");
    return s;
}

PassIO HybridPass::describe() const {
    PassIO io;
    io.roles.framepassOwn = true;
    io.roles.tracesRays = true;  // bench replays its rays in bare Embree loops
    io.inputs = {
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit (0) pixels are skipped"),
        {.name = ssgi::kFurthestHzb, .channels = {"Z"}, .doc = "furthest HZB (device Z)"},
        {.name = ssgi::kReducedColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "last frame's colour, reprojected and reduced to 5 mips: what on-screen hits read"},
    };
    if (mParams.continueOnScreen) {
        io.inputs.push_back(gbuffer::baseColorInput("continueOnScreen: the hit's diffuse colour"));
        io.inputs.push_back(gbuffer::metallicInput("DiffuseColor = BaseColor·(1 − Metallic)"));
    }
    io.outputs = {
        {.name = ssgi::kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "mean incoming radiance of the rays (irradiance/π), on-screen and fallback hits "
                "together; 0 on skipped pixels"},
        {.name = ssgi::kAo,
         .channels = {"Y"},
         .doc = "1 − fraction of rays that hit, on screen or in the scene (as "
                "Truth.AOAnyDistance); 1 on skipped pixels"},
        {.name = ssgi::kHitMask,
         .channels = {"Y"},
         .doc = "debug: fraction of rays that hit on screen or in the scene"},
        {.name = ssgi::kHitDistance,
         .channels = {"Y"},
         .doc = "debug: mean distance to the hits, scene units (0: no hit)"},
    };
    io.needsCamera = true;
    io.needsScene = true;
    io.workUnit = "rays";
    return io;
}

hybrid::GiFallback<BvhTracer> HybridPass::bvhFallback(PassContext& ctx, const BvhTracer& tracer,
                                                      unsigned long long* counts) const {
    const RayScene& rs = ctx.scene();
    const CameraView& cam = ctx.frame().camera.current;
    hybrid::GiFallback<BvhTracer> f{};
    f.tracer = tracer;
    f.paths.bounces = mParams.maxBounces;
    f.paths.nee = mParams.nextEventEstimationSamples;
    f.onward = f.paths;
    f.onward.bounces = mParams.maxBounces - 1;
    f.continuing = mParams.continueOnScreen && mParams.maxBounces > 1;
    f.cam = cam;
    f.eyeOffset = cam.position - rs.origin();
    f.bias = RayBias::fromCm(mParams.normalBias, float(rs.scene().centimetre()));
    f.rngKey = Rng::frameKey(ctx.frame().number, kSeed);
    f.onwardKey = Rng::frameKey(ctx.frame().number, kOnwardSeed);
    f.wantDistance = ctx.isRequested(ssgi::kHitDistance);
    f.counts = counts;
    return f;
}

void HybridPass::addFallbackWork(PassContext& ctx, uint64_t rays,
                                 const unsigned long long* counts) const {
    using namespace hybrid;
    ctx.addWork("onScreenRays", rays - counts[kFallbackRays]);
    ctx.addWork("fallbackRays", counts[kFallbackRays]);
    ctx.addWork("fallbackHits", counts[kFallbackHits]);
    ctx.addWork("continuedHits", counts[kContinued]);
    ctx.addWork("sceneRays", counts[kSceneRays]);
    ctx.addWork("shadowRays", counts[kShadowRays]);
}

uint64_t HybridPass::traceWaves(PassContext& ctx, const HostPorts& ports, int rays, int steps,
                                const hybrid::EmbreeFallback& fallback,
                                const DiffusePathSetup& missSetup,
                                const DiffusePathSetup& onwardSetup) const {
    const ssgi::Frame f = ssgi::bindFrame(ports, ctx.frame(), rays, steps, false, 1.0f);
    std::array<std::atomic<uint64_t>, ssgi::kCounterCount> totals{};
    std::atomic<uint64_t> sceneRays{0}, shadowRays{0};
    const bool wantDistance = bool(f.hitDistance);
    forEachTile(f.ao.width, f.ao.height, [&](const Tile& t) {
        // Each worker's arrays, kept from tile to tile (a tile's are some megabytes).
        thread_local hybrid::TileMarch m;
        // 1. The march over the tile, a pixel's rays in SIMD lanes, recorded, with its work (the
        //    skipped pixels' outputs written as ssgi::run writes them).
        WorkCounts<ssgi::kCounterCount> counts{};
        hybrid::recordTileMarch(f, t, fallback, m, counts.value);
        // 2. Its scene paths as waves: the k-th path of each pixel's stream together, k = 0, 1,
        //    …, so each stream draws its paths in the order the march asked for them.
        uint64_t scene = 0, shadow = 0;
        uint32_t fallbackHits = 0, continued = 0;
        m.missResults.resize(m.misses.size());
        // Where each on-screen hit continues from, read from the GBuffer at the hit: a tight loop
        // whose reads overlap, each hit's started some hits ahead (the march would wait on each).
        const std::size_t hits = m.continuationHits.size();
        m.continuations.resize(hits);
        constexpr std::size_t kAhead = 8;
        for (std::size_t i = 0; i < hits; ++i) {
            if (i + kAhead < hits) {
                const PixelCoord q = fallback.continuationPixel(m.continuationHits[i + kAhead]);
                for (const PlaneView* plane :
                     {&fallback.depth, &fallback.shadingModel, &fallback.normal[0],
                      &fallback.normal[1], &fallback.normal[2], &fallback.baseColor[0],
                      &fallback.baseColor[1], &fallback.baseColor[2], &fallback.metallic})
                    __builtin_prefetch(plane->data + planeIndex(q.x, q.y, plane->stride));
            }
            m.continuations[i] = fallback.continuation(m.continuationHits[i]);
        }
        m.continuationResults.assign(hits, Vec3f{});
        const std::size_t pixels = m.tracedPixels();
        for (std::size_t k = 0;; ++k) {
            m.going.clear();
            m.rngs.clear();
            m.owner.clear();
            for (std::size_t p = 0; p < pixels; ++p) {
                const std::size_t i = m.pixels[p].firstMiss + k;
                if (i >= m.pixels[p + 1].firstMiss) continue;
                m.going.push_back(m.misses[i]);
                m.rngs.push_back(&m.pixels[p].rng);
                m.owner.push_back(i);
            }
            if (m.going.empty()) break;
            m.wave.trace(missSetup, m.going.data(), m.rngs.data(), int(m.going.size()), scene,
                         shadow);
            for (std::size_t g = 0; g < m.going.size(); ++g) {
                const ssgi::RayTrace hit = fallback.missTrace(m.going[g].out);
                fallbackHits += hit.hit;
                m.missResults[m.owner[g]] = hit;
            }
        }
        for (std::size_t k = 0;; ++k) {
            m.going.clear();
            m.rngs.clear();
            m.owner.clear();
            bool asked = false;
            for (std::size_t p = 0; p < pixels; ++p) {
                const std::size_t i = m.pixels[p].firstContinuation + k;
                if (i >= m.pixels[p + 1].firstContinuation) continue;
                asked = true;
                const hybrid::EmbreeFallback::Continuation& c = m.continuations[i];
                if (!c.valid) continue;  // nothing drawn, nothing added
                m.going.push_back(fallback.continuationPath(c, m.pixels[p].onwardRng));
                m.rngs.push_back(&m.pixels[p].onwardRng);
                m.owner.push_back(i);
            }
            if (!asked) break;
            continued += uint32_t(m.going.size());
            m.wave.trace(onwardSetup, m.going.data(), m.rngs.data(), int(m.going.size()), scene,
                         shadow);
            for (std::size_t g = 0; g < m.going.size(); ++g)
                m.continuationResults[m.owner[g]] =
                    m.continuations[m.owner[g]].diffuseColor * m.going[g].out.radiance;
        }
        // 3. Each traced pixel resolved from its rays' light in ray order, as the march would
        //    have summed it with each path traced where it asked (HybridKernel.h's miss and
        //    onScreenHit).
        for (std::size_t p = 0; p < pixels; ++p) {
            const hybrid::TileMarch::Pixel& pixel = m.pixels[p];
            ssgi::PixelStart start{};
            if (wantDistance) {  // an on-screen hit's distance, from the pixel (beginPixel's)
                const PixelCoord q = fullResPixel(pixel.x, pixel.y, f.toFull, f.width, f.height);
                start = ssgi::pixelStart(f, pixel.x, pixel.y, q.x, q.y, f.depth.at(q.x, q.y));
            }
            ssgi::PixelTrace trace;
            for (std::size_t i = pixel.firstRay; i < m.pixels[p + 1].firstRay; ++i) {
                const hybrid::TileMarch::Ray& r = m.rays[i];
                if (r.kind == hybrid::TileMarch::kScreen) {
                    trace.add(r.screen);
                } else if (r.kind == hybrid::TileMarch::kMiss) {
                    trace.add(m.missResults[r.path]);
                } else {
                    float c[3] = {r.color[0], r.color[1], r.color[2]};
                    if (m.continuations[r.path].valid) {
                        const Vec3f& more = m.continuationResults[r.path];
                        c[0] += more.x, c[1] += more.y, c[2] += more.z;
                    }
                    trace.add(ssgi::weighHit(f.setup, start, r.hit, c, wantDistance));
                }
            }
            ssgi::finishPixel(f, pixel.x, pixel.y, trace);
        }
        for (int i = 0; i < ssgi::kCounterCount; ++i) totals[std::size_t(i)] += counts.value[i];
        sceneRays += scene;
        shadowRays += shadow;
        unsigned long long* shared = fallback.counts;
        addSharedCount(shared + hybrid::kFallbackRays, m.misses.size());
        addSharedCount(shared + hybrid::kFallbackHits, fallbackHits);
        addSharedCount(shared + hybrid::kContinued, continued);
    });
    addSharedCount(fallback.counts + hybrid::kSceneRays, sceneRays.load());
    addSharedCount(fallback.counts + hybrid::kShadowRays, shadowRays.load());
    std::array<uint64_t, ssgi::kCounterCount> result{};
    for (int i = 0; i < ssgi::kCounterCount; ++i) result[std::size_t(i)] = totals[std::size_t(i)];
    ssgi::reportWork(ctx, result);
    return result[ssgi::kRays];
}

void HybridPass::execute(PassContext& ctx) {
    const SSGIQuality q = SSGIPass::traced(mParams.quality, mParams.rays);
    const RayScene& rs = ctx.scene();
    const DirectLighting lighting(rs, 1);
    unsigned long long counts[hybrid::kHybridCounters] = {};
    const HostPorts ports{ctx};
    std::shared_ptr<const LightView> lights;
    hybrid::GiFallback<BvhTracer> bvh = bvhFallback(ctx, bvhTracerFor(ports, lighting, lights), counts);
    hybrid::bindPlanes(ports, bvh);
    uint64_t rays = 0;  // SSGI's, on screen and not
    if (mParams.traversal == "bvh") {
        rays = ssgi::run(ctx, ports, CpuPixels{}, q.rays, q.steps, false, 1.0f, bvh,
                         "hybrid")[ssgi::kRays];
    } else {
        DiffusePathSetup paths;
        paths.scene = &rs;
        paths.lighting = &lighting;
        const hybrid::GiFallback<EmbreeTracer> embree{
            EmbreeTracer{paths}, bvh.paths, bvh.onward, bvh.continuing, bvh.cam, bvh.eyeOffset,
            bvh.bias, bvh.rngKey, bvh.onwardKey, bvh.wantDistance, bvh.depth,
            {bvh.normal[0], bvh.normal[1], bvh.normal[2]}, bvh.shadingModel,
            {bvh.baseColor[0], bvh.baseColor[1], bvh.baseColor[2]}, bvh.metallic, counts};
        if (mParams.waves) {
            DiffusePathSetup missSetup = paths, onwardSetup = paths;
            static_cast<DiffusePathSettings&>(missSetup) = embree.paths;
            static_cast<DiffusePathSettings&>(onwardSetup) = embree.onward;
            rays = traceWaves(ctx, ports, q.rays, q.steps, embree, missSetup, onwardSetup);
        } else {
            rays = ssgi::run(ctx, ports, CpuPixels{}, q.rays, q.steps, false, 1.0f, embree,
                             "hybrid")[ssgi::kRays];
        }
    }
    addFallbackWork(ctx, rays, counts);
}

}  // namespace fp
