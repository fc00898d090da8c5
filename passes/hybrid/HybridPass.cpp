#include "passes/hybrid/HybridPass.h"

#include "foundation/PerPixel.h"
#include "framework/PassPorts.h"
#include "passes/hybrid/HybridKernel.h"
#include "passes/ssgi/SSGIKernel.h"
#include "passes/ssgi/SSGIPass.h"
#include "screenspace/GBuffer.h"
#include "shading/DiffusePaths.h"
#include "shading/RayOriginBias.h"

#include <algorithm>
#include <array>

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

void HybridPass::execute(PassContext& ctx) {
    const SSGIQuality q = SSGIPass::traced(mParams.quality, mParams.rays);
    const RayScene& rs = ctx.scene();
    const DirectLighting lighting(rs, 1);
    unsigned long long counts[hybrid::kHybridCounters] = {};
    const HostPorts ports{ctx};
    std::shared_ptr<const LightView> lights;
    hybrid::GiFallback<BvhTracer> bvh = bvhFallback(ctx, bvhTracerFor(ports, lighting, lights), counts);
    hybrid::bindPlanes(ports, bvh);
    std::array<uint64_t, ssgi::kCounterCount> ssgiCounts;
    if (mParams.traversal == "bvh") {
        ssgiCounts = ssgi::run(ctx, ports, CpuPixels{}, q.rays, q.steps, false, 1.0f, bvh, "hybrid");
    } else {
        DiffusePathSetup paths;
        paths.scene = &rs;
        paths.lighting = &lighting;
        const hybrid::GiFallback<EmbreeTracer> embree{
            EmbreeTracer{paths}, bvh.paths, bvh.onward, bvh.continuing, bvh.cam, bvh.eyeOffset,
            bvh.bias, bvh.rngKey, bvh.onwardKey, bvh.wantDistance, bvh.depth,
            {bvh.normal[0], bvh.normal[1], bvh.normal[2]}, bvh.shadingModel,
            {bvh.baseColor[0], bvh.baseColor[1], bvh.baseColor[2]}, bvh.metallic, counts};
        ssgiCounts = ssgi::run(ctx, ports, CpuPixels{}, q.rays, q.steps, false, 1.0f, embree, "hybrid");
    }
    addFallbackWork(ctx, ssgiCounts[ssgi::kRays], counts);
}

}  // namespace fp
