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
#include "shading/DirectLighting.h"
#include "shading/RayOriginBias.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kDiffuse = "diffuse";
constexpr const char* kAo = "ao";
constexpr const char* kHitDistance = "hitDistance";
constexpr uint32_t kSeed = 0x52544749u;    // "RTGI"
constexpr float kMinNormalBiasCm = 0.01f;  // r.RayTracing.NormalBias's floor, as rt_shadows
constexpr float kTMinCm = 0.01f;           // the first ray's TMin

// What every pixel of a frame shares.
struct Setup {
    const RayScene* rs;
    const DirectLighting* lighting;
    const std::vector<Light>* lights;
    const SkyLight* sky;  // null: no sky radiance on a miss
    CameraView camera;
    Vec3d eyeOffset;
    int spp, bounces, nee;
    float giDistance, aoRadius, tMin, maxBias, minBias, diffuseThreshold;
    uint32_t rngKey;
};

// One pixel's sums over its paths.
struct PixelSums {
    Vec3f radiance;
    int aoHits = 0, hits = 0;
    double hitDistance = 0;
};

// The diffuse light the lights send to hit `s` through next event estimation: each of `nee`
// samples picks one light uniformly and traces its shadow ray; the sum is scaled by the light
// count over the sample count (the pick's pdf).
Vec3f sampleLights(const Setup& c, const SurfacePoint& s, Rng& rng, uint64_t& shadowRays) {
    const int n = int(c.lights->size());
    Vec3f sum;
    if (n == 0 || c.nee <= 0) return sum;
    for (int k = 0; k < c.nee; ++k) {
        const float pick = rng.nextFloat(), u = rng.nextFloat(), v = rng.nextFloat();
        const Light& light = (*c.lights)[std::min(int(pick * float(n)), n - 1)];
        const LightSample ls = c.lighting->sample(light, s, u, v);
        const float cosine = dot(s.normal, ls.L);
        if (!ls.reaches() || cosine <= 0.0f) continue;
        ++shadowRays;
        if (!c.lighting->visible(s, ls)) continue;
        sum += s.brdf.diffuseColor * ls.irradiance * (cosine / kPiF);
    }
    return sum * (float(n) / float(c.nee));
}

// One path from the pixel's surface along the cosine direction drawn from `rng`.
void tracePath(const Setup& c, const Vec3f& p, const Vec3f& n, const Vec3f& toEye, float eyeDistance,
               Rng& rng, PixelSums& sums, uint64_t& rays, uint64_t& shadowRays) {
    const float u = rng.nextFloat(), v = rng.nextFloat();
    Vec3f dir = cosineHemisphere(n, u, v);
    Vec3f org = biasedRayOrigin(p, toEye, eyeDistance, n, dot(n, dir), c.maxBias, c.minBias);
    float tMin = c.tMin;
    Vec3f throughput{1, 1, 1};  // the pixel's own albedo is divided out (the composite applies it)
    const float reach = std::max(c.giDistance, c.aoRadius);
    for (int bounce = 0; bounce < c.bounces; ++bounce) {
        ++rays;
        const RayHit hit = c.rs->intersect(org, dir, tMin, reach);
        if (!hit.hit) {
            if (c.sky && bounce > 0) sums.radiance += throughput * c.sky->radiance(dir);
            return;
        }
        if (bounce == 0) {
            ++sums.hits;
            sums.hitDistance += hit.t;
            if (hit.t < c.aoRadius) ++sums.aoHits;
        }
        if (hit.t > c.giDistance) return;
        const SurfacePoint s = surfaceAt(*c.rs, hit, org, dir);
        // No emission at hits: Unreal adds only the lights' light (and no lightmap).
        sums.radiance += throughput * sampleLights(c, s, rng, shadowRays);
        if (bounce + 1 == c.bounces) return;
        // The next diffuse bounce: BxDF·cos/pdf = DiffuseColor.
        const float bu = rng.nextFloat(), bv = rng.nextFloat();
        dir = cosineHemisphere(s.normal, bu, bv);
        org = s.rayOrigin();
        tMin = 0.0f;
        throughput = throughput * s.brdf.diffuseColor;
    }
}

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
    return s;
}

PassIO RTGlobalIlluminationPass::describe() const {
    PassIO io;
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
    const Extent size = ctx.frame().extent;
    Image& diffuse = ctx.output(kDiffuse, {size}).image();
    Plane& ao = ctx.output(kAo, {size}).image().plane(0);
    Plane& hitDistance = ctx.output(kHitDistance, {size}).image().plane(0);
    const RayScene& rs = ctx.scene();
    const DirectLighting lighting(rs, 1);
    const CameraView& cam = ctx.frame().camera.current;
    const float cm = float(rs.scene().centimetre());
    Setup c{};
    c.rs = &rs;
    c.lighting = &lighting;
    c.lights = &rs.scene().lights;
    c.sky = mParams.evalSkyLight && rs.scene().environment.sky.enabled ? &rs.scene().environment.sky
                                                                       : nullptr;
    c.camera = cam;
    c.eyeOffset = cam.position - rs.origin();
    c.spp = mParams.samplesPerPixel > 0 ? mParams.samplesPerPixel : 4;
    c.bounces = mParams.maxBounces > 0 ? mParams.maxBounces : 1;
    c.nee = mParams.nextEventEstimationSamples;
    c.giDistance = float(std::min(double(mParams.maxRayDistance) * cm, 1e30));
    c.aoRadius = mParams.aoRadius * cm;
    c.tMin = kTMinCm * cm;
    c.maxBias = std::max(mParams.normalBias, kMinNormalBiasCm) * cm;
    c.minBias = kMinNormalBiasCm * cm;
    c.diffuseThreshold = mParams.diffuseThreshold;
    c.rngKey = Rng::frameKey(ctx.frame().number, kSeed);

    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Plane& model = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Image& normal = ctx.input(gbuffer::kNormal)->image();
    const Image& baseColor = ctx.input(gbuffer::kBaseColor)->image();
    const Plane& metallic = ctx.input(gbuffer::kMetallic)->image().plane(0);

    forEachTile(size.width, size.height, [&](const Tile& t) {
        uint64_t rays = 0, shadowRays = 0, pixels = 0, skipped = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const double d = depth.at(x, y);
                const float m = metallic.at(x, y);
                const Vec3f albedo{baseColor.plane(0).at(x, y), baseColor.plane(1).at(x, y),
                                   baseColor.plane(2).at(x, y)};
                // A subsurface-profile pixel's diffuse colour is its stored base colour.
                const bool profile = truncToInt(model.at(x, y), 0, 255) == kSubsurfaceProfile;
                const Vec3f diffuseColor = profile ? albedo : albedo * (1.0f - m);
                if (!isLitSurface(d, model.at(x, y)) ||
                    ue::luma(diffuseColor.x, diffuseColor.y, diffuseColor.z) < c.diffuseThreshold) {
                    for (int ch = 0; ch < 3; ++ch) diffuse.plane(ch).at(x, y) = 0.0f;
                    ao.at(x, y) = 0.0f;
                    hitDistance.at(x, y) = -1.0f;
                    ++skipped;
                    continue;
                }
                const Vec3d offset = cam.translatedFromPixel(x, y, d);
                const Vec3f p(c.eyeOffset + offset);
                const double eyeDistance = length(offset);
                const Vec3f toEye(-offset / eyeDistance);
                const Vec3f n{normal.plane(0).at(x, y), normal.plane(1).at(x, y),
                              normal.plane(2).at(x, y)};
                Rng rng = Rng::fromKey(c.rngKey, x, y);
                PixelSums sums;
                for (int k = 0; k < c.spp; ++k)
                    tracePath(c, p, n, toEye, float(eyeDistance), rng, sums, rays, shadowRays);
                const float inv = 1.0f / float(c.spp);
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
