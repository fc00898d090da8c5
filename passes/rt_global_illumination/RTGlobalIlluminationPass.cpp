#include "passes/rt_global_illumination/RTGlobalIlluminationPass.h"

#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/Random.h"
#include "foundation/RayScene.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "foundation/Tiles.h"
#include "foundation/UnrealRandom.h"
#include "framework/PassPorts.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Surface.h"
#include "screenspace/TraceResolution.h"
#include "passes/rt_global_illumination/RTGlobalIlluminationKernel.h"
#include "shading/DiffusePathWave.h"
#include "shading/DiffusePaths.h"
#include "shading/RayOriginBias.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

using rtgi::kAo;
using rtgi::kDiffuse;
using rtgi::kHitDistance;
constexpr uint32_t kSeed = 0x52544749u;    // "RTGI"
constexpr float kTMinCm = 0.01f;           // the first ray's TMin

}  // namespace

ParamSpec<RTGlobalIlluminationParams> RTGlobalIlluminationPass::paramSpec() {
    ParamSpec<RTGlobalIlluminationParams> s;
    s.add("samplesPerPixel", &Params::samplesPerPixel,
          "paths per pixel; −1 = the post-process volume's RayTracingGISamplesPerPixel (4)")
        .range(-1, 256)
        .cvar("r.RayTracing.GlobalIllumination.SamplesPerPixel");
    s.add("maxBounces", &Params::maxBounces,
          "diffuse bounces per path; −1 = the post-process volume's RayTracingGIMaxBounces (1)")
        .range(-1, 64)
        .cvar("r.RayTracing.GlobalIllumination.MaxBounces");
    s.add("maxRayDistance", &Params::maxRayDistance,
          "cm: a hit beyond this ends the path (Unreal's default 1e27: none)")
        .range(0.0, 1e30)
        .cvar("r.RayTracing.GlobalIllumination.MaxRayDistance");
    s.add("aoRadius", &Params::aoRadius,
          "cm: the post-process AmbientOcclusionRadius; a first hit closer than this counts in ao")
        .range(0.0, 1e9);
    s.add("nextEventEstimationSamples", &Params::nextEventEstimationSamples,
          "light samples (one light picked uniformly, one shadow ray) at each hit")
        .range(0, 64)
        .cvar("r.RayTracing.GlobalIllumination.NextEventEstimationSamples");
    s.add("evalSkyLight", &Params::evalSkyLight,
          "a bounce ray (not the first) that misses adds the scene's sky radiance")
        .cvar("r.RayTracing.GlobalIllumination.EvalSkyLight");
    s.add("diffuseThreshold", &Params::diffuseThreshold,
          "pixels whose diffuse colour's luminance is below this trace nothing")
        .range(0.0, 1.0)
        .cvar("r.RayTracing.GlobalIllumination.DiffuseThreshold");
    s.add("normalBias", &Params::normalBias, "largest normal/camera bias, cm (at N·L = 0)")
        .range(0.01, 1e6)
        .cvar("r.RayTracing.NormalBias");
    s.add("screenPercentage", &Params::screenPercentage,
          "traces one pixel of each k×k block, k = int(100 / this) (Unreal's default 50 applies "
          "with its denoiser, which upscales: gi_denoise does); 100 traces every pixel")
        .range(25.0, 100.0)
        .cvar("r.RayTracing.GlobalIllumination.ScreenPercentage");
    s.add("traversal", &Params::traversal,
          "\"embree\": Embree's scene; \"bvh\": framepass's own BVH, the code the GPU runs (on "
          "the GPU the pass always traverses it; its paths read no sky, so with evalSkyLight the "
          "pass runs on the CPU and \"bvh\" is refused)")
        .choices({"embree", "bvh"});
    s.add("waves", &Params::waves,
          "with Embree, a tile row's paths traced together a step at a time, each step's shadow "
          "rays in Embree's packets (false: each path to its end one ray at a time; the same "
          "bits)");
    return s;
}

int RTGlobalIlluminationPass::upscale() const {
    return screenPercentageUpscale(mParams.screenPercentage);
}

std::vector<Extent> RTGlobalIlluminationPass::outputExtents(std::string_view, Extent frame) const {
    return {traceExtent(frame, upscale())};
}

PassIO RTGlobalIlluminationPass::describe() const {
    PassIO io;
    io.roles.unrealSwitch = "r.RayTracing.GlobalIllumination=1";  // brute force
    io.roles.tracesRays = true;  // bench replays its rays in bare Embree loops
    io.roles.raysParam = "samplesPerPixel";  // the error breakdown's ray-traced ladder
    io.roles.bouncesParam = "maxBounces";
    io.inputs = {
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit and sky pixels are skipped"),
        gbuffer::baseColorInput("with metallic, the diffuse colour that skips dark pixels"),
        gbuffer::metallicInput("DiffuseColor = BaseColor·(1 − Metallic)"),
    };
    io.outputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .doc = "mean path radiance (irradiance/π, as ssgi.diffuse): DiffuseColor × this is the "
                "indirect diffuse light"},
        {.name = kAo,
         .channels = {"Y"},
         .doc = "1 − the fraction of first rays that hit within aoRadius (0 where skipped)"},
        {.name = kHitDistance,
         .channels = {"Y"},
         .doc = "mean first-hit distance, scene units; −1 where no ray hit or skipped"},
    };
    io.needsCamera = true;
    io.needsScene = true;
    io.workUnit = "rays";
    return io;
}

rtgi::FrameSetup RTGlobalIlluminationPass::frameSetup(PassContext& ctx) const {
    const RayScene& rs = ctx.scene();
    const CameraView& cam = ctx.frame().camera.current;
    const float cm = float(rs.scene().centimetre());
    rtgi::FrameSetup s{};
    s.camera = cam;
    s.eyeOffset = cam.position - rs.origin();
    s.frame = ctx.frame().extent;
    s.upscale = upscale();
    s.spp = mParams.samplesPerPixel > 0 ? mParams.samplesPerPixel : 4;
    s.aoRadius = mParams.aoRadius * cm;
    s.tMin = kTMinCm * cm;
    s.diffuseThreshold = mParams.diffuseThreshold;
    s.bias = RayBias::fromCm(mParams.normalBias, cm);
    s.paths.bounces = mParams.maxBounces > 0 ? mParams.maxBounces : 1;
    s.paths.nee = mParams.nextEventEstimationSamples;
    s.paths.giDistance = float(std::min(double(mParams.maxRayDistance) * cm, 1e30));
    s.paths.reach = std::max(s.paths.giDistance, s.aoRadius);
    s.rngKey = Rng::frameKey(ctx.frame().number, kSeed);
    return s;
}

void RTGlobalIlluminationPass::execute(PassContext& ctx) {
    const rtgi::FrameSetup setup = frameSetup(ctx);
    const Extent trace = outputExtents(kDiffuse, ctx.frame().extent).front();
    const RayScene& rs = ctx.scene();
    const DirectLighting lighting(rs, 1);
    const SkyLight* sky = mParams.evalSkyLight && rs.scene().environment.sky.enabled
                              ? &rs.scene().environment.sky
                              : nullptr;
    if (mParams.traversal == "bvh") {
        if (sky)
            throw UsageError("rt_global_illumination: traversal \"bvh\" reads no sky, and "
                             "evalSkyLight asks for it with the scene's sky on: use traversal "
                             "\"embree\"");
        std::shared_ptr<const LightView> lights;
        rtgi::run(ctx, HostPorts{ctx}, CpuPixels{}, setup, trace,
                  bvhTracerFor(HostPorts{ctx}, lighting, lights), "rt_global_illumination");
        return;
    }
    DiffusePathSetup paths;
    static_cast<DiffusePathSettings&>(paths) = setup.paths;
    paths.scene = &rs;
    paths.lighting = &lighting;
    paths.sky = sky;
    if (!mParams.waves) {
        rtgi::run(ctx, HostPorts{ctx}, CpuPixels{}, setup, trace, EmbreeTracer{paths},
                  "rt_global_illumination");
        return;
    }
    const rtgi::Frame f = rtgi::frameOf(HostPorts{ctx}, setup, trace);
    forEachTile(trace.width, trace.height, [&](const Tile& t) {
        // A row at a time: every texel set up, then its k-th paths traced together as a wave,
        // k = 0, 1, …: each texel's stream draws its paths in order, as texelStep does.
        DiffusePathWave wave;
        std::vector<rtgi::Texel> texels(std::size_t(t.x1 - t.x0));
        std::vector<PathState> going;
        std::vector<Rng*> rngs;
        std::vector<int> owner;
        uint64_t rays = 0, shadowRays = 0, pixels = 0;
        for (int y = t.y0; y < t.y1; ++y) {
            rngs.clear();
            owner.clear();
            for (int x = t.x0; x < t.x1; ++x) {
                rtgi::Texel& texel = texels[std::size_t(x - t.x0)];
                texel = rtgi::texelAt(f, x, y);
                if (!texel.traced) continue;
                rngs.push_back(&texel.rng);
                owner.push_back(x - t.x0);
            }
            pixels += owner.size();
            going.resize(owner.size());
            for (int k = 0; k < setup.spp; ++k) {
                for (std::size_t i = 0; i < owner.size(); ++i)
                    going[i] = rtgi::texelPath(setup, texels[std::size_t(owner[i])]);
                wave.trace(paths, going.data(), rngs.data(), int(going.size()), rays, shadowRays);
                for (std::size_t i = 0; i < owner.size(); ++i)
                    rtgi::addPath(setup, texels[std::size_t(owner[i])], going[i].out);
            }
            for (int x = t.x0; x < t.x1; ++x) rtgi::writeTexel(f, texels[std::size_t(x - t.x0)], x, y);
        }
        ctx.addWork("rays", rays);
        ctx.addWork("shadowRays", shadowRays);
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", uint64_t(t.x1 - t.x0) * uint64_t(t.y1 - t.y0) - pixels);
    });
}

}  // namespace fp
