#include "passes/diffuse_indirect_composite/DiffuseIndirectCompositePass.h"

#include "passes/common/GBuffer.h"
#include "passes/core/Error.h"
#include "passes/core/FloatToInt.h"
#include "passes/core/ShadingModel.h"
#include "passes/core/Tiles.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {
constexpr const char* kSceneColor = "sceneColor";
constexpr const char* kDiffuse = "diffuse";
constexpr const char* kAo = "ao";
constexpr const char* kColor = "color";

// The SSGI signal at its trace resolution and what its UE5 half-resolution upsample compares.
struct SsgiInputs {
    const Image& ssgi;
    int width, height;  // the frame
    bool half;          // traced at half resolution
    bool depthTested;   // UE5: the 2×2 upsample drops taps on other surfaces
    const Plane* depth;
    const CameraView* cam;
};

// The SSGI radiance for full-resolution pixel (x, y). 4.27: point sample. UE5 at half resolution:
// 2×2 bilinear with taps on other surfaces dropped, then renormalised.
void sampleSsgi(const SsgiInputs& in, int x, int y, float e[3]) {
    const Image& ssgi = in.ssgi;
    if (!in.half || !in.depthTested) {
        const int tx = in.half ? x / 2 : x, ty = in.half ? y / 2 : y;
        for (int c = 0; c < 3; ++c)
            e[c] = ssgi.plane(c).at(tx, ty);
        return;
    }
    const int W = in.width, H = in.height;
    const int TW = ssgi.width(), TH = ssgi.height();
    const double d = in.depth->at(x, y);
    const Vec3d ref = in.cam->translatedFromPixel(x, y, d);
    const double maxDist =
        DiffuseIndirectCompositePass::kUpsampleRejection * in.cam->pixelRadiusAtDepth(d);
    // Half-res texel i sits on full-res pixel 2i: full pixel x is at texel coordinate x/2.
    const int x0 = x / 2, y0 = y / 2;
    const float fx = (x & 1) ? 0.5f : 0.0f, fy = (y & 1) ? 0.5f : 0.0f;
    float sum[3] = {0, 0, 0}, wSum = 0.0f;
    for (int k = 0; k < 4; ++k) {
        const int tx = std::min(x0 + (k & 1), TW - 1), ty = std::min(y0 + (k >> 1), TH - 1);
        const float w = ((k & 1) ? fx : 1 - fx) * ((k >> 1) ? fy : 1 - fy);
        if (w <= 0.0f)
            continue;
        const int px = std::min(2 * tx, W - 1), py = std::min(2 * ty, H - 1);
        const double td = in.depth->at(px, py);
        if (std::isinf(td))
            continue;
        const Vec3d p = in.cam->translatedFromPixel(px, py, td) - ref;
        if (dot(p, p) > maxDist * maxDist)
            continue;
        for (int c = 0; c < 3; ++c)
            sum[c] += w * ssgi.plane(c).at(tx, ty);
        wSum += w;
    }
    // Every tap on another surface: the nearest texel [inferred; Unreal's normalisation of
    // zero weight is not transcribed].
    for (int c = 0; c < 3; ++c)
        e[c] = wSum > 0.0f ? sum[c] / wSum : ssgi.plane(c).at(x0, y0);
}

// The GBuffer planes of the diffuse colour.
struct AlbedoInputs {
    const Image& baseColor;
    const Plane& metallic;
    const Image* customData;  // UE5 only
};

// Reference §7.2–7.3: the diffuse colour SSGI is multiplied by, per channel. Subsurface profile
// and eye keep their real albedo (StoredBaseColor) and have no metalness; everyone else's
// DiffuseColor = BaseColor·(1 − Metallic); UE5 adds the subsurface / fuzz colour.
void diffuseAlbedo(const AlbedoInputs& in, int model, int x, int y, float albedo[3]) {
    const bool storedBase = model == kSubsurfaceProfile || model == kEye;
    const float m = storedBase ? 0.0f : in.metallic.at(x, y);
    for (int c = 0; c < 3; ++c) {
        albedo[c] = in.baseColor.plane(c).at(x, y) * (1.0f - m);
        if (in.customData) {
            const float cd = in.customData->plane(c).at(x, y);
            const float extra = cd * cd;  // CustomData holds √colour (§1.7)
            if (model == kSubsurface || model == kPreintegratedSkin || model == kTwoSidedFoliage)
                albedo[c] += extra;
            else if (model == kCloth)
                albedo[c] += extra * in.customData->plane(3).at(x, y);
        }
    }
}
}  // namespace

ParamSpec<DiffuseIndirectCompositeParams> DiffuseIndirectCompositePass::paramSpec() {
    ParamSpec<DiffuseIndirectCompositeParams> s;
    s.add("engine", &Params::engine,
          "ue4.27: SceneColor×AO + DiffuseColor×SSGI, point upsample; ue5: per-shading-model "
          "diffuse terms and a depth-tested 2×2 upsample")
        .choices({"ue4.27", "ue5"});
    s.add("aoStaticFraction", &Params::aoStaticFraction,
          "post-process AmbientOcclusionStaticFraction: how much of the AO darkens scene colour")
        .range(0.0, 1.0);
    return s;
}

PassIO DiffuseIndirectCompositePass::describe() const {
    PassIO io;
    io.inputs = {
        {.name = kSceneColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .captureDefault = "SceneColor",
         .doc = "emissive + precomputed light before direct lighting"},
        gbuffer::baseColorInput(),
        gbuffer::metallicInput("metalness"),
        gbuffer::shadingModelInput("shading model id"),
        gbuffer::gbufferAOInput(false),
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "denoised SSGI radiance (trace resolution)"},
        {.name = kAo, .channels = {"Y"}, .doc = "denoised SSGI AO"},
    };
    if (ue5()) {
        io.inputs.push_back(
            gbuffer::customDataInput("subsurface / fuzz colour (√) and amounts", false));
        io.inputs.push_back(gbuffer::depthInput("depth for the half-resolution upsample test"));
    }
    io.outputs = {{.name = kColor,
                   .channels = {"R", "G", "B"},
                   .kind = PortKind::Color,
                   .doc = "scene colour with diffuse indirect and AO applied"}};
    io.needsCamera = ue5();
    return io;
}

void DiffuseIndirectCompositePass::execute(PassContext& ctx) {
    const Image& sceneColor = ctx.input(kSceneColor)->image();
    const Plane& shadingModel = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Plane& gbufferAO = ctx.input(gbuffer::kGBufferAO)->image().plane(0);
    const Image& ssgi = ctx.input(kDiffuse)->image();
    const Plane& dynamicAO = ctx.input(kAo)->image().plane(0);
    const int W = sceneColor.width(), H = sceneColor.height();
    const int TW = ssgi.width(), TH = ssgi.height();
    const bool half = TW < W || TH < H;
    FP_CHECK(TW == (half ? (W + 1) / 2 : W) && TH == (half ? (H + 1) / 2 : H),
             "the SSGI input is {}×{}: neither the frame's {}×{} nor half of it", TW, TH, W, H);
    const SsgiInputs signal{ssgi,
                            W,
                            H,
                            half,
                            ue5(),
                            ue5() ? &ctx.input(gbuffer::kDepth)->image().plane(0) : nullptr,
                            ue5() ? &ctx.frame().camera.current : nullptr};
    const AlbedoInputs albedoIn{ctx.input(gbuffer::kBaseColor)->image(),
                                ctx.input(gbuffer::kMetallic)->image().plane(0),
                                ue5() ? &ctx.input(gbuffer::kCustomData)->image() : nullptr};
    Texture& out = ctx.output(kColor, {{W, H}});

    forEachTile(W, H, [&](const Tile& t) {
        uint64_t pixels = 0, skipped = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const int model = truncToInt(shadingModel.at(x, y), 0, 255);
                float rgb[3] = {sceneColor.plane(0).at(x, y), sceneColor.plane(1).at(x, y),
                                sceneColor.plane(2).at(x, y)};
                if (model == kUnlit) {  // AOMask = 0 and no diffuse: colour is untouched
                    for (int c = 0; c < 3; ++c)
                        out.image().plane(c).at(x, y) = rgb[c];
                    ++skipped;
                    continue;
                }
                ++pixels;
                // reference §7.1: FinalAO = lerp(1, GBufferAO × DynamicAO, staticFraction).
                const float dyn = dynamicAO.at(half ? x / 2 : x, half ? y / 2 : y);
                const float finalAO =
                    1.0f + (gbufferAO.at(x, y) * dyn - 1.0f) * mParams.aoStaticFraction;
                float e[3], albedo[3];
                sampleSsgi(signal, x, y, e);
                diffuseAlbedo(albedoIn, model, x, y, albedo);
                for (int c = 0; c < 3; ++c)
                    out.image().plane(c).at(x, y) = rgb[c] * finalAO + albedo[c] * e[c];
            }
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", skipped);
    });
}

}  // namespace fp
