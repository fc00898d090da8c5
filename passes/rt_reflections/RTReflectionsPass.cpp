#include "passes/rt_reflections/RTReflectionsPass.h"

#include "foundation/Environment.h"
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
#include "shading/ReflectionHits.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kReflection = "reflection";
constexpr const char* kHitDistance = "hitDistance";
constexpr uint32_t kSeed = 0x52545246u;     // "RTRF"
constexpr float kMirrorRoughness = 0.001f;  // below it the ray is the mirror direction
constexpr float kImportantSampleBias = 0.1f;  // GGX_IMPORTANT_SAMPLE_BIAS: the tail left out
constexpr float kSkyHitDistance = 1e20f;      // Unreal's hit distance for a ray that saw the sky
constexpr float kHybridDepthCm = 5.0f;        // hybrid: a hit this close behind the depth buffer is the pixel's
constexpr const char* kSceneColor = "sceneColor";

// Unreal's RoughnessFade: 1 up to half the cutoff, 0 at it.
float roughnessFade(float roughness, float maxRoughness) {
    return std::clamp(2.0f - 2.0f * roughness / maxRoughness, 0.0f, 1.0f);
}

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

void RTReflectionsPass::execute(PassContext& ctx) {
    const Extent frame = ctx.frame().extent;
    const int upscale = screenPercentageUpscale(mParams.screenPercentage);
    const Extent size = traceExtent(frame, upscale);
    Image& reflection = ctx.output(kReflection, {size}).image();
    Plane& hitDistance = ctx.output(kHitDistance, {size}).image().plane(0);
    const RayScene& rs = ctx.scene();
    mSky = ReflectedSky::of(rs.scene().environment.sky, mSky);
    const ReflectedSky* sky = mSky.get();
    const DirectLighting lighting(rs, 1);
    const ReflectionHitLighting hitLighting{&rs, &lighting, sky, mParams.shadows != 0,
                                            mParams.hitIndirectBounces};
    const CameraView& cam = ctx.frame().camera.current;
    const float cm = float(rs.scene().centimetre());
    const Vec3d eyeOffset = cam.position - rs.origin();
    const int spp = mParams.samplesPerPixel > 0 ? mParams.samplesPerPixel : 1;
    const float maxRoughness =
        std::clamp(mParams.maxRoughness < 0.0f ? 0.6f : mParams.maxRoughness, 0.01f, 1.0f);
    const RayBias bias = RayBias::fromCm(mParams.normalBias, cm);
    const uint32_t rngKey = Rng::frameKey(ctx.frame().number, kSeed);

    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Plane& model = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Image& normal = ctx.input(gbuffer::kNormal)->image();
    const Plane& roughnessPlane = ctx.input(gbuffer::kRoughness)->image().plane(0);
    const Image* sceneColor = mParams.hybrid ? &ctx.input(kSceneColor)->image() : nullptr;
    const float hybridDepth = kHybridDepthCm * cm;

    forEachTile(size.width, size.height, [&](const Tile& t) {
        uint64_t rays = 0, pixels = 0, skipped = 0, skyRays = 0, screenHits = 0;
        ReflectionHitWork hitWork;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                // Texel (x, y) traces from the top-left pixel of its block (§12.2's convention).
                const auto [px, py] = fullResPixel(x, y, upscale, frame.width, frame.height);
                const double d = depth.at(px, py);
                const float roughness = roughnessPlane.at(px, py);
                const float fade = roughnessFade(roughness, maxRoughness);
                if (!isLitSurface(d, model.at(px, py)) || truncToInt(model.at(px, py), 0, 255) == kHair ||
                    fade <= 0.0f) {
                    for (int c = 0; c < 4; ++c) reflection.plane(c).at(x, y) = 0.0f;
                    hitDistance.at(x, y) = -2.0f;
                    ++skipped;
                    continue;
                }
                const PixelSurface surface = pixelSurface(cam, eyeOffset, px, py, d);
                const Vec3f& V = surface.toEye;
                const Vec3f N{normal.plane(0).at(px, py), normal.plane(1).at(px, py),
                              normal.plane(2).at(px, py)};
                Rng rng = Rng::fromKey(rngKey, px, py);
                Vec3f sum;
                double distanceSum = 0;
                int hits = 0, sawSky = 0;
                for (int k = 0; k < spp; ++k) {
                    const float e1 = rng.nextFloat(), e2 = rng.nextFloat();
                    Vec3f L;
                    if (roughness < kMirrorRoughness) {
                        L = reflect(V, N);
                    } else {
                        // GGX visible normals with a² = roughness⁴; the disk's radius coordinate
                        // scaled by 0.9 leaves out the lobe's tail.
                        const Vec3f H = sampleGgxVisibleNormal(N, V, roughness * roughness,
                                                               e2 * (1.0f - kImportantSampleBias), e1);
                        L = reflect(V, H);
                    }
                    const float NoL = dot(N, L);
                    if (NoL < 0.0f) L = normalize(L - N * (2.0f * NoL));  // mirrored back above
                    const Vec3f org = biasedRayOrigin(surface, N, dot(N, L), bias);
                    ++rays;
                    const RayHit hit = rs.intersect(org, L, 0.0f, std::numeric_limits<float>::infinity());
                    if (!hit.hit) {
                        if (sky) {
                            sum += sky->miss(L, roughness);
                            ++sawSky;
                        }
                        continue;
                    }
                    ++hits;
                    distanceSum += hit.t;
                    const Vec3f hitPoint = org + L * hit.t;  // relative to the scene's origin
                    if (sceneColor) {
                        // Unreal's hybrid: on screen, in front of the camera, and at most 5 cm
                        // behind the depth buffer there: the lit colour of that pixel, point
                        // sampled, no shading.
                        const CameraView::Projection pr = cam.projectOffset(Vec3d(hitPoint), rs.origin());
                        if (pr.depth > 0.0 && pr.px >= 0.0 && pr.py >= 0.0 && pr.px < frame.width &&
                            pr.py < frame.height) {
                            const int hx = int(pr.px), hy = int(pr.py);
                            const double there = depth.at(hx, hy);
                            if (std::isfinite(there) && pr.depth - there < hybridDepth) {
                                sum += Vec3f{sceneColor->plane(0).at(hx, hy),
                                             sceneColor->plane(1).at(hx, hy),
                                             sceneColor->plane(2).at(hx, hy)};
                                ++screenHits;
                                continue;
                            }
                        }
                    }
                    // Hybrid: shaded hits look from the camera, so both kinds match (knowingly
                    // wrong for the specular term, as in Unreal).
                    const Vec3f fromCamera =
                        sceneColor ? normalize(Vec3f(eyeOffset) - hitPoint) : Vec3f{};
                    sum += shadeReflectionHit(hitLighting, hit, org, L, rng, hitWork,
                                              sceneColor ? &fromCamera : nullptr);
                }
                const float scale = fade / float(spp);
                reflection.plane(0).at(x, y) = sum.x * scale;
                reflection.plane(1).at(x, y) = sum.y * scale;
                reflection.plane(2).at(x, y) = sum.z * scale;
                // Coverage: the samples that found something (a surface, or the sky); a miss
                // with no sky light leaves its share to the reflection captures.
                reflection.plane(3).at(x, y) = fade * float(hits + sawSky) / float(spp);
                hitDistance.at(x, y) = hits > 0 ? float(distanceSum / hits)
                                                : (sawSky > 0 ? kSkyHitDistance : -1.0f);
                skyRays += uint64_t(sawSky);
                ++pixels;
            }
        ctx.addWork("rays", rays);
        ctx.addWork("shadowRays", hitWork.shadowRays);
        if (mParams.hitIndirectBounces > 0) ctx.addWork("indirectRays", hitWork.indirectRays);
        ctx.addWork("skyRays", skyRays);
        if (sceneColor) ctx.addWork("screenHits", screenHits);
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", skipped);
    });
}

}  // namespace fp
