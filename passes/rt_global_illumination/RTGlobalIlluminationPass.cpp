#include "passes/rt_global_illumination/RTGlobalIlluminationPass.h"

#include "foundation/Camera.h"
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
#include "shading/DiffusePaths.h"
#include "shading/RayOriginBias.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kDiffuse = "diffuse";
constexpr const char* kAo = "ao";
constexpr const char* kHitDistance = "hitDistance";
constexpr uint32_t kSeed = 0x52544749u;    // "RTGI"
constexpr float kTMinCm = 0.01f;           // the first ray's TMin

// One pixel's sums over its paths.
struct PixelSums {
    Vec3f radiance;
    int aoHits = 0, hits = 0;
    double hitDistance = 0;
};

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

void RTGlobalIlluminationPass::execute(PassContext& ctx) {
    const Extent frame = ctx.frame().extent;
    const int k = upscale();
    const Extent size = outputExtents(kDiffuse, frame).front();
    Image& diffuse = ctx.output(kDiffuse, {size}).image();
    Plane& ao = ctx.output(kAo, {size}).image().plane(0);
    Plane& hitDistance = ctx.output(kHitDistance, {size}).image().plane(0);
    const RayScene& rs = ctx.scene();
    const DirectLighting lighting(rs, 1);
    const CameraView& cam = ctx.frame().camera.current;
    const float cm = float(rs.scene().centimetre());
    const Vec3d eyeOffset = cam.position - rs.origin();
    const int spp = mParams.samplesPerPixel > 0 ? mParams.samplesPerPixel : 4;
    const float aoRadius = mParams.aoRadius * cm, tMin = kTMinCm * cm;
    const RayBias bias = RayBias::fromCm(mParams.normalBias, cm);
    DiffusePathSetup paths;
    paths.scene = &rs;
    paths.lighting = &lighting;
    paths.lights = &rs.scene().lights;
    paths.sky = mParams.evalSkyLight && rs.scene().environment.sky.enabled
                    ? &rs.scene().environment.sky
                    : nullptr;
    paths.bounces = mParams.maxBounces > 0 ? mParams.maxBounces : 1;
    paths.nee = mParams.nextEventEstimationSamples;
    paths.giDistance = float(std::min(double(mParams.maxRayDistance) * cm, 1e30));
    paths.reach = std::max(paths.giDistance, aoRadius);
    const uint32_t rngKey = Rng::frameKey(ctx.frame().number, kSeed);

    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Plane& model = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Image& normal = ctx.input(gbuffer::kNormal)->image();
    const Image& baseColor = ctx.input(gbuffer::kBaseColor)->image();
    const Plane& metallic = ctx.input(gbuffer::kMetallic)->image().plane(0);

    forEachTile(size.width, size.height, [&](const Tile& t) {
        uint64_t rays = 0, shadowRays = 0, pixels = 0, skipped = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                // Texel (x, y) traces from the top-left pixel of its k × k block.
                const auto [px, py] = fullResPixel(x, y, k, frame.width, frame.height);
                const double d = depth.at(px, py);
                const float m = metallic.at(px, py);
                const Vec3f albedo{baseColor.plane(0).at(px, py), baseColor.plane(1).at(px, py),
                                   baseColor.plane(2).at(px, py)};
                const Vec3f diffuseColor = gbufferDiffuseColor(albedo, m, model.at(px, py));
                if (!isLitSurface(d, model.at(px, py)) ||
                    ue::luma(diffuseColor.x, diffuseColor.y, diffuseColor.z) < mParams.diffuseThreshold) {
                    for (int ch = 0; ch < 3; ++ch) diffuse.plane(ch).at(x, y) = 0.0f;
                    ao.at(x, y) = 0.0f;
                    hitDistance.at(x, y) = -1.0f;
                    ++skipped;
                    continue;
                }
                const PixelSurface surface = pixelSurface(cam, eyeOffset, px, py, d);
                const Vec3f n{normal.plane(0).at(px, py), normal.plane(1).at(px, py),
                              normal.plane(2).at(px, py)};
                Rng rng = Rng::fromKey(rngKey, px, py);
                PixelSums sums;
                for (int k = 0; k < spp; ++k) {
                    // A cosine ray about the GBuffer normal from the biased position (§12.2).
                    const float u = rng.nextFloat(), v = rng.nextFloat();
                    const Vec3f dir = cosineHemisphere(n, u, v);
                    const Vec3f org = biasedRayOrigin(surface, n, dot(n, dir), bias);
                    const DiffusePath path =
                        traceDiffusePath(paths, org, dir, tMin, rng, rays, shadowRays);
                    sums.radiance += path.radiance;
                    if (path.firstHit >= 0.0f) {
                        ++sums.hits;
                        sums.hitDistance += path.firstHit;
                        if (path.firstHit < aoRadius) ++sums.aoHits;
                    }
                }
                const float inv = 1.0f / float(spp);
                diffuse.plane(0).at(x, y) = sums.radiance.x * inv;
                diffuse.plane(1).at(x, y) = sums.radiance.y * inv;
                diffuse.plane(2).at(x, y) = sums.radiance.z * inv;
                ao.at(x, y) = 1.0f - float(sums.aoHits) * inv;
                hitDistance.at(x, y) = sums.hits > 0 ? float(sums.hitDistance / sums.hits) : -1.0f;
                ++pixels;
            }
        ctx.addWork("rays", rays);
        ctx.addWork("shadowRays", shadowRays);
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", skipped);
    });
}

}  // namespace fp
