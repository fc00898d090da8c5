#include "passes/reflection_environment/ReflectionEnvironmentPass.h"

#include "screenspace/GBuffer.h"
#include "foundation/Environment.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "foundation/Tiles.h"
#include "shading/BRDF.h"
#include "shading/EnvBRDF.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kColor = "color";
constexpr const char* kReflection = "reflection";
constexpr const char* kAo = "ao";
constexpr const char* kSpecular = "specular";
constexpr const char* kDiffuse = "diffuse";

// Unreal's F0 for the clear coat's own interface (algorithms §8.2 step 8).
constexpr float kCoatF0 = 0.04f;

Vec3f rgbAt(const Image& im, int x, int y) {
    return {im.plane(0).at(x, y), im.plane(1).at(x, y), im.plane(2).at(x, y)};
}

// NaN and negatives to 0 (§8.2 step 9).
Vec3f finiteNonNegative(const Vec3f& c) {
    auto f = [](float v) { return v > 0.0f && v < std::numeric_limits<float>::infinity() ? v : 0.0f; };
    return {f(c.x), f(c.y), f(c.z)};
}

// The off-specular peak (§8.2 step 2): rough lobes lean from the mirror direction towards N.
Vec3f dominantDirection(const Vec3f& N, const Vec3f& R, float roughness) {
    const float a = roughness * roughness;
    const float t = (1.0f - a) * (std::sqrt(1.0f - a) + a);
    return normalize(N * (1.0f - t) + R * t);
}

}  // namespace

ParamSpec<ReflectionEnvironmentParams> ReflectionEnvironmentPass::paramSpec() {
    ParamSpec<ReflectionEnvironmentParams> s;
    s.add("reflections", &Params::reflections,
          "the specular half: screen-space reflections, then the reflection captures and the "
          "sky's prefiltered radiance, × EnvBRDF")
        .cvar("r.ReflectionEnvironment");
    s.add("skyDiffuse", &Params::skyDiffuse, "the sky light's diffuse (SH3 irradiance × DiffuseColor)");
    s.add("specularOcclusion", &Params::specularOcclusion,
          "Lagarde's specular occlusion from GBuffer AO × screen-space AO on what the reflections "
          "leave to the sky");
    return s;
}

PassIO ReflectionEnvironmentPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::sceneColorInput(kColor, "the lit colour the reflections and sky light add to"),
        gbuffer::depthInput("linear view depth (position and view direction)"),
        gbuffer::normalInput(),
        gbuffer::baseColorInput(),
        gbuffer::metallicInput("metalness (F0 and DiffuseColor)"),
        gbuffer::specularInput("dielectric specular (F0 = 0.08 × specular)"),
        gbuffer::roughnessInput("roughness: EnvBRDF, the sky's mip, the off-specular peak"),
        gbuffer::shadingModelInput("shading model id (unlit untouched, hair without reflections)"),
        gbuffer::customDataInput("subsurface / fuzz colour (√) and clear coat, roughness", true),
        gbuffer::gbufferAOInput(true),
        {.name = kReflection,
         .channels = {"R", "G", "B", "A"},
         .kind = PortKind::Color,
         .optional = true,
         .doc = "screen-space reflections: premultiplied radiance, A = coverage (none: 0)"},
        {.name = kAo,
         .channels = {"Y"},
         .optional = true,
         .doc = "screen-space AO (SSGI's), full or half resolution (none: 1)"},
    };
    io.outputs = {
        {.name = kColor, .channels = {"R", "G", "B"}, .kind = PortKind::Color,
         .doc = "the colour with the sky light's diffuse and the reflections added"},
        {.name = kSpecular, .channels = {"R", "G", "B"}, .kind = PortKind::Color,
         .doc = "the reflected specular that was added (SSR, sky, × EnvBRDF)"},
        {.name = kDiffuse, .channels = {"R", "G", "B"}, .kind = PortKind::Color,
         .doc = "the sky light's diffuse that was added"},
    };
    io.needsCamera = true;
    io.needsEnvironment = true;
    return io;
}

float ReflectionEnvironmentPass::specularOcclusion(float NoV, float ao, float roughness) {
    return saturate(std::pow(NoV + ao, roughness * roughness) - 1.0f + ao);
}

const ReflectionEnvironmentPass::SkyLighting& ReflectionEnvironmentPass::skyLighting(const SkyLight& sky) {
    if (!mSky || mSky->source != &sky) {
        auto s = std::make_shared<SkyLighting>();
        s->source = &sky;
        s->cube = Cubemap::render(kSkyCubeSize, [&](const Vec3f& d) { return sky.radiance(d); });
        s->sh = s->cube.projectSH();
        mSky = std::move(s);
    }
    return *mSky;
}

const std::vector<Cubemap>& ReflectionEnvironmentPass::captureCubes(const Environment& env) {
    if (mCubesOf != &env || mCaptureCubes.size() != env.captures.size()) {
        mCaptureCubes.clear();
        for (const ReflectionCapture& c : env.captures) mCaptureCubes.push_back(Cubemap::fromFaces(c.faces));
        mCubesOf = &env;
    }
    return mCaptureCubes;
}

void ReflectionEnvironmentPass::execute(PassContext& ctx) {
    const Image& in = ctx.input(kColor)->image();
    const int W = in.width(), H = in.height();
    Image& out = ctx.output(kColor, {{W, H}}).image();
    Image* specOut = ctx.isRequested(kSpecular) ? &ctx.output(kSpecular, {{W, H}}).image() : nullptr;
    Image* diffOut = ctx.isRequested(kDiffuse) ? &ctx.output(kDiffuse, {{W, H}}).image() : nullptr;

    const Environment& env = ctx.environment();
    const Texture* ssr = ctx.input(kReflection);
    const bool sky = env.sky.enabled;
    const bool doSpecular = mParams.reflections && (sky || ssr || !env.captures.empty());
    const bool doDiffuse = mParams.skyDiffuse && sky;
    if (!doSpecular && !doDiffuse) {
        // Nothing lights the reflections: the colour passes through and no GBuffer is read.
        copyPixels(in, out);
        ctx.addWork("skippedPixels", uint64_t(W) * H);
        return;
    }
    const SkyLighting* skyLight = sky ? &skyLighting(env.sky) : nullptr;
    const CameraView& cam = ctx.frame().camera.current;
    // The captures relative to this frame's eye, in the environment's (ascending radius) order.
    std::vector<PreparedCapture> captures;
    if (mParams.reflections && !env.captures.empty()) {
        const std::vector<Cubemap>& cubes = captureCubes(env);
        for (std::size_t i = 0; i < env.captures.size(); ++i) {
            const ReflectionCapture& c = env.captures[i];
            PreparedCapture p;
            p.box = c.shape == ReflectionCapture::Shape::Box;
            p.centre = Vec3f(c.position - cam.position);
            p.radius = float(c.radius);
            p.extent = Vec3f(c.extent);
            p.transition = float(c.transitionDistance);
            p.brightness = c.brightness;
            p.offset = Vec3f(c.offset);
            p.cube = &cubes[i];
            captures.push_back(p);
        }
    }
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Image& normal = ctx.input(gbuffer::kNormal)->image();
    const Image& baseColor = ctx.input(gbuffer::kBaseColor)->image();
    const Plane& metallic = ctx.input(gbuffer::kMetallic)->image().plane(0);
    const Plane& specular = ctx.input(gbuffer::kSpecular)->image().plane(0);
    const Plane& roughnessPlane = ctx.input(gbuffer::kRoughness)->image().plane(0);
    const Plane& shadingModel = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Texture* customData = ctx.input(gbuffer::kCustomData);
    const Texture* gbufferAO = ctx.input(gbuffer::kGBufferAO);
    const Texture* aoTex = ctx.input(kAo);
    const Image* ssrImage = ssr ? &ssr->image() : nullptr;
    const Plane* ao = aoTex ? &aoTex->image().plane(0) : nullptr;
    const bool halfAo = ao && (ao->width() < W || ao->height() < H);
    if (ao)
        FP_CHECK(ao->width() == (halfAo ? (W + 1) / 2 : W) && ao->height() == (halfAo ? (H + 1) / 2 : H),
                 "the AO input is {}×{}: neither the frame's {}×{} nor half of it", ao->width(),
                 ao->height(), W, H);
    if (ssrImage)
        FP_CHECK(ssrImage->width() == W && ssrImage->height() == H,
                 "the reflection input is {}×{}, the frame {}×{}", ssrImage->width(), ssrImage->height(), W, H);
    const EnvBRDFLut& lut = EnvBRDFLut::instance();
    // Without a sky or captures, a pixel the SSR left empty (rough, missed, faded) gets nothing.
    auto ssrEmptyAt = [&](int x, int y) {
        return !ssrImage || (ssrImage->plane(3).at(x, y) == 0.0f && ssrImage->plane(0).at(x, y) == 0.0f &&
                             ssrImage->plane(1).at(x, y) == 0.0f && ssrImage->plane(2).at(x, y) == 0.0f);
    };

    // The specular of one layer (§8.2 steps 2–6): SSR, then the captures and the sky in what it
    // leaves, under specular occlusion. EnvBRDF is the caller's, since clear coat weighs its two layers apart.
    auto layer = [&](const Vec3f& P, const Vec3f& N, const Vec3f& V, float NoV, float roughness,
                     const Vec3f& ssrColor, float ssrAlpha, float occlusionAO) {
        Vec3f color = ssrColor;
        float alpha = 1.0f - ssrAlpha;
        if (mParams.specularOcclusion) alpha *= specularOcclusion(NoV, occlusionAO, roughness);
        if (alpha <= 0.0f || (!skyLight && captures.empty())) return color;
        const Vec3f R = dominantDirection(N, reflect(V, N), roughness);
        color += compositeCaptures(captures, P, R, roughness, alpha);
        if (skyLight && alpha > 0.0f)
            color += skyLight->cube.sample(R, skyLight->cube.mipForRoughness(roughness)) * alpha;
        return color;
    };

    forEachTile(W, H, [&](const Tile& t) {
        uint64_t lit = 0, skipped = 0, empty = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const Vec3f before = rgbAt(in, x, y);
                const double d = depth.at(x, y);
                const int model = truncToInt(shadingModel.at(x, y), 0, 255);
                Vec3f diffuse, spec;
                if (!isLitSurface(d, shadingModel.at(x, y))) {
                    ++skipped;
                } else if (!sky && captures.empty() && ssrEmptyAt(x, y)) {
                    ++empty;
                } else {
                    ++lit;
                    const Vec3f N = normalize(gbuffer::worldNormalAt(normal, x, y));
                    const Vec3d p = cam.translatedFromPixel(x, y, d);
                    const Vec3f P{float(p.x), float(p.y), float(p.z)};
                    const Vec3f V = normalize(-P);
                    const Vec3f base = rgbAt(baseColor, x, y);
                    const SurfaceBRDF brdf = SurfaceBRDF::fromMaterial(
                        base, metallic.at(x, y), specular.at(x, y), roughnessPlane.at(x, y));
                    Vec3f cd;
                    float cdA = 0.0f;
                    if (customData) {
                        const Image& c = customData->image();
                        cd = {c.plane(0).at(x, y), c.plane(1).at(x, y), c.plane(2).at(x, y)};
                        cdA = c.plane(3).at(x, y);
                    }
                    const float materialAO = gbufferAO ? gbufferAO->image().plane(0).at(x, y) : 1.0f;
                    const float screenAO = ao ? ao->at(halfAo ? x / 2 : x, halfAo ? y / 2 : y) : 1.0f;
                    if (doDiffuse) {
                        // §8.1: sky visibility 1 (no distance-field AO), combined with the AO by
                        // Minimum; subsurface-type colours are stored as √colour (§1.7).
                        const float s = std::min(materialAO, screenAO);
                        Vec3f albedo = model == kSubsurfaceProfile || model == kEye ? base : brdf.diffuseColor;
                        const Vec3f extra = cd * cd;
                        if (model == kSubsurface || model == kPreintegratedSkin) albedo += extra;
                        if (model == kCloth) albedo += extra * cdA;
                        diffuse = (skyLight->sh.diffuse(N) * s + env.sky.occlusionTint * (1.0f - s)) * albedo;
                        if (model == kTwoSidedFoliage) diffuse += skyLight->sh.diffuse(-N) * extra * s;
                    }
                    if (doSpecular && model != kHair) {
                        const float NoV = saturate(dot(N, V));
                        const float roughness = brdf.roughness;
                        const float occlusionAO = materialAO * screenAO;
                        Vec3f ssrColor;
                        float ssrAlpha = 0.0f;
                        if (ssrImage) {
                            ssrColor = rgbAt(*ssrImage, x, y);
                            ssrAlpha = saturate(ssrImage->plane(3).at(x, y));
                        }
                        const EnvBRDFTerms terms = lut.lookup(NoV, roughness);
                        if (model == kClearCoat && customData) {
                            // §8.2 steps 4 and 8: the base loses the SSR to the coat and its
                            // grazing term, and sees what the coat's Fresnel lets through.
                            const float coat = saturate(cd.x), coatRoughness = saturate(cd.y);
                            const Vec3f baseColorLayer =
                                layer(P, N, V, NoV, roughness, ssrColor * (1.0f - coat),
                                      ssrAlpha * (1.0f - coat), occlusionAO);
                            const Vec3f baseBrdf =
                                applyEnvBRDF(brdf.specularColor, {terms.a, terms.b * (1.0f - coat)});
                            const EnvBRDFTerms coatTerms = lut.lookup(NoV, coatRoughness);
                            const float coatF = (kCoatF0 * coatTerms.a + coatTerms.b) * coat;
                            spec = baseColorLayer * baseBrdf * (1.0f - coatF) +
                                   layer(P, N, V, NoV, coatRoughness, ssrColor, ssrAlpha, occlusionAO) * coatF;
                        } else {
                            spec = layer(P, N, V, NoV, roughness, ssrColor, ssrAlpha, occlusionAO) *
                                   applyEnvBRDF(brdf.specularColor, terms);
                        }
                    }
                }
                diffuse = finiteNonNegative(diffuse);
                spec = finiteNonNegative(spec);
                const Vec3f after = before + diffuse + spec;
                out.plane(0).at(x, y) = after.x;
                out.plane(1).at(x, y) = after.y;
                out.plane(2).at(x, y) = after.z;
                if (specOut)
                    for (int c = 0; c < 3; ++c) specOut->plane(c).at(x, y) = spec[c];
                if (diffOut)
                    for (int c = 0; c < 3; ++c) diffOut->plane(c).at(x, y) = diffuse[c];
            }
        ctx.addWork("pixels", lit);
        ctx.addWork("skippedPixels", skipped);
        ctx.addWork("emptyPixels", empty);
    });
}

}  // namespace fp
