#include "passes/hybrid/HybridPass.h"

#include "foundation/Tiles.h"
#include "framework/PassPorts.h"
#include "passes/ssgi/SSGIKernel.h"
#include "passes/ssgi/SSGIPass.h"
#include "screenspace/GBuffer.h"
#include "shading/DiffusePaths.h"
#include "shading/RayOriginBias.h"

#include <algorithm>

namespace fp {

namespace {

constexpr uint32_t kSeed = 0x48594252u;    // "HYBR"
constexpr uint32_t kOnwardSeed = 0x4F4E5744u;  // "ONWD"

// Work counted per tile.
struct HybridWork {
    uint64_t pixels = 0, skipped = 0, onScreen = 0, fallback = 0, fallbackHits = 0, rays = 0,
             shadowRays = 0, hzbSamples = 0, continued = 0;
};

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

void HybridPass::execute(PassContext& ctx) {
    const SSGIQuality q = SSGIPass::traced(mParams.quality, mParams.rays);
    const ssgi::Frame f = ssgi::bindFrame(HostPorts{ctx}, ctx.frame(), q.rays, q.steps, false, 1.0f);
    const RayScene& rs = ctx.scene();
    const DirectLighting lighting(rs, 1);
    const CameraView& cam = ctx.frame().camera.current;
    const float cm = float(rs.scene().centimetre());
    const Vec3d eyeOffset = cam.position - rs.origin();
    const RayBias bias = RayBias::fromCm(mParams.normalBias, cm);
    DiffusePathSetup paths;
    paths.scene = &rs;
    paths.lighting = &lighting;
    paths.lights = &rs.scene().lights;
    paths.bounces = mParams.maxBounces;
    paths.nee = mParams.nextEventEstimationSamples;
    const uint32_t rngKey = Rng::frameKey(ctx.frame().number, kSeed);
    const uint32_t onwardKey = Rng::frameKey(ctx.frame().number, kOnwardSeed);
    const bool wantDistance = bool(f.hitDistance);

    // continueOnScreen: the paths after an on-screen hit, from the hit pixel's GBuffer surface.
    const bool continuing = mParams.continueOnScreen && mParams.maxBounces > 1;
    DiffusePathSetup onward = paths;
    onward.bounces = mParams.maxBounces - 1;
    const Image* baseColor = continuing ? &ctx.input(gbuffer::kBaseColor)->image() : nullptr;
    const Plane* metallic = continuing ? &ctx.input(gbuffer::kMetallic)->image().plane(0) : nullptr;
    const int W = f.depth.width, H = f.depth.height;
    auto continuePath = [&](const RayPoint& hit, Rng& rng, HybridWork& work) -> Vec3f {
        // The hit's half-resolution position, on the full-resolution GBuffer.
        const int px = std::clamp(int(hit.hx * 2.0f), 0, W - 1);
        const int py = std::clamp(int(hit.hy * 2.0f), 0, H - 1);
        const double d = f.depth.at(px, py);
        if (!isLitSurface(d, f.shadingModel.at(px, py)))
            return {};
        const Vec3f diffuseColor = gbufferDiffuseColor(
            {baseColor->plane(0).at(px, py), baseColor->plane(1).at(px, py),
             baseColor->plane(2).at(px, py)},
            metallic->at(px, py), f.shadingModel.at(px, py));
        const Vec3f hn = normalize(
            Vec3f{f.normal[0].at(px, py), f.normal[1].at(px, py), f.normal[2].at(px, py)});
        const float u = rng.nextFloat(), v = rng.nextFloat();
        const Vec3f dir = cosineHemisphere(hn, u, v);
        const Vec3f org = biasedRayOrigin(pixelSurface(cam, eyeOffset, px, py, d), hn, dot(hn, dir), bias);
        ++work.continued;
        const DiffusePath path = traceDiffusePath(onward, org, dir, 0.0f, rng, work.rays, work.shadowRays);
        return diffuseColor * path.radiance;
    };

    forEachTile(f.ao.width, f.ao.height, [&](const Tile& t) {
        HybridWork work;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                unsigned long long counts[ssgi::kCounterCount] = {};
                ssgi::PixelStart start;
                if (!ssgi::beginPixel(f, x, y, counts, start)) {
                    ++work.skipped;
                    continue;
                }
                ++work.pixels;
                // The fallback rays' common origin: the pixel's surface as the RT passes leave it.
                const double d = f.depth.at(x, y);
                const PixelSurface surface = pixelSurface(cam, eyeOffset, x, y, d);
                const Vec3f n{f.normal[0].at(x, y), f.normal[1].at(x, y), f.normal[2].at(x, y)};
                Rng rng = Rng::fromKey(rngKey, x, y);
                // The continued paths draw from their own sequence, so the fallback rays are
                // the same with continueOnScreen as without.
                Rng onwardRng = Rng::fromKey(onwardKey, x, y);
                ssgi::PixelTrace trace;
                unsigned hzbSamples = 0;
                for (int r = 0; r < f.setup.rays; ++r) {
                    // SSGI's ray and march (algorithms §4.4–4.7), unchanged.
                    const Vec3f L =
                        ssgi::rayDirection(start.nView, x, y, f.setup.frameMod8, r, f.setup.rays);
                    RaySteps steps;
                    if (ssgi::raySteps(f.setup, start, L, steps)) {
                        float level;
                        const int hitSample = marchHzb(f.setup.hzb, steps, f.setup.steps,
                                                       f.setup.levelStep, level, hzbSamples);
                        if (hitSample >= 0) {
                            ++work.onScreen;
                            if (!continuing) {
                                trace.add(ssgi::shadeHit(f.setup, start, steps, hitSample, level,
                                                         wantDistance));
                                continue;
                            }
                            // Last frame's colour at the hit, plus the hit surface's diffuse
                            // colour × one cosine path of the bounces after it (§12.3).
                            const RayPoint hit = rayPointAt(steps, float(hitSample));
                            float c[3];
                            ssgi::hitColor(f.setup, hit, level, c);
                            const Vec3f more = continuePath(hit, onwardRng, work);
                            c[0] += more.x, c[1] += more.y, c[2] += more.z;
                            trace.add(ssgi::weighHit(f.setup, start, hit, c, wantDistance));
                            continue;
                        }
                    }
                    // The march found nothing: the same direction through the scene, from the
                    // pixel (a march that saw nothing may still have passed behind a surface).
                    ++work.fallback;
                    const Vec3f dir = normalize(Vec3f(cam.right) * L.x + Vec3f(cam.up) * L.y +
                                                Vec3f(cam.forward) * L.z);
                    const Vec3f org = biasedRayOrigin(surface, n, dot(n, dir), bias);
                    const DiffusePath path =
                        traceDiffusePath(paths, org, dir, 0.0f, rng, work.rays, work.shadowRays);
                    if (path.firstHit < 0.0f) continue;  // left the scene: no light, as a miss
                    ++work.fallbackHits;
                    // Weighted as SSGI weighs an on-screen hit, so the pixel's resolve undoes
                    // one weighting over all its hits (algorithms §4.7–4.8).
                    ssgi::RayTrace hit;
                    const Vec3f c = path.radiance;
                    const float karis = 1.0f / (1.0f + ue::luma(c.x, c.y, c.z));
                    hit.weighted[0] = c.x * karis;
                    hit.weighted[1] = c.y * karis;
                    hit.weighted[2] = c.z * karis;
                    hit.hit = true;
                    hit.measured = wantDistance;
                    hit.distance = path.firstHit;
                    trace.add(hit);
                }
                work.hzbSamples += hzbSamples;
                ssgi::finishPixel(f, x, y, trace);
            }
        ctx.addWork("pixels", work.pixels);
        ctx.addWork("skippedPixels", work.skipped);
        ctx.addWork("rays", work.onScreen + work.fallback);
        ctx.addWork("onScreenRays", work.onScreen);
        ctx.addWork("fallbackRays", work.fallback);
        ctx.addWork("fallbackHits", work.fallbackHits);
        ctx.addWork("continuedHits", work.continued);
        ctx.addWork("sceneRays", work.rays);
        ctx.addWork("shadowRays", work.shadowRays);
        ctx.addWork("hzbSamples", work.hzbSamples);
    });
}

}  // namespace fp
