#pragma once
// The diffuse-indirect composite's per-pixel work (algorithms §7), for
// DiffuseIndirectCompositePass::execute and DiffuseIndirectCompositePass.cu alike.
#include "screenspace/GBuffer.h"
#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/ShadingModel.h"
#include "passes/diffuse_indirect_composite/DiffuseIndirectCompositePass.h"

#include <algorithm>
#include <cmath>

namespace fp::composite {

inline constexpr const char* kSceneColor = "sceneColor";
inline constexpr const char* kDiffuse = "diffuse";
inline constexpr const char* kAo = "ao";
inline constexpr const char* kColor = "color";

/// Everything one frame's pixels read and write.
struct Frame {
    PlaneView sceneColor[3], shadingModel, gbufferAO, ssgi[3], dynamicAO;
    PlaneView baseColor[3], metallic;
    PlaneView customData[4];  //!< UE5 only (null otherwise)
    PlaneView depth;          //!< UE5 only
    CameraView cam;           //!< UE5 only
    PlaneSpan out[3];
    int width, height;  //!< the frame
    bool half;          //!< SSGI traced at half resolution
    bool depthTested;   //!< UE5: the 2×2 upsample drops taps on other surfaces
    float aoStaticFraction;
};

// The SSGI radiance for full-resolution pixel (x, y). 4.27: point sample. UE5 at half resolution:
// 2×2 bilinear with taps on other surfaces dropped, then renormalised.
FP_HD inline void sampleSsgi(const Frame& f, int x, int y, float e[3]) {
    if (!f.half || !f.depthTested) {
        const int tx = f.half ? x / 2 : x, ty = f.half ? y / 2 : y;
        for (int c = 0; c < 3; ++c)
            e[c] = f.ssgi[c].at(tx, ty);
        return;
    }
    const int W = f.width, H = f.height;
    const int TW = f.ssgi[0].width, TH = f.ssgi[0].height;
    const double d = f.depth.at(x, y);
    const Vec3d ref = f.cam.translatedFromPixel(x, y, d);
    const double maxDist =
        DiffuseIndirectCompositePass::kUpsampleRejection * f.cam.pixelRadiusAtDepth(d);
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
        const double td = f.depth.at(px, py);
        if (std::isinf(td))
            continue;
        const Vec3d p = f.cam.translatedFromPixel(px, py, td) - ref;
        if (dot(p, p) > maxDist * maxDist)
            continue;
        for (int c = 0; c < 3; ++c)
            sum[c] += w * f.ssgi[c].at(tx, ty);
        wSum += w;
    }
    // Every tap on another surface: the nearest texel [inferred; Unreal's normalisation of
    // zero weight is not transcribed].
    for (int c = 0; c < 3; ++c)
        e[c] = wSum > 0.0f ? sum[c] / wSum : f.ssgi[c].at(x0, y0);
}

// algorithms §7.2–7.3: the diffuse colour SSGI is multiplied by, per channel. Subsurface profile
// and eye keep their real albedo (StoredBaseColor) and have no metalness; everyone else's
// DiffuseColor = BaseColor·(1 − Metallic); UE5 adds the subsurface / fuzz colour.
FP_HD inline void diffuseAlbedo(const Frame& f, int model, int x, int y, float albedo[3]) {
    const bool storedBase = model == kSubsurfaceProfile || model == kEye;
    const float m = storedBase ? 0.0f : f.metallic.at(x, y);
    for (int c = 0; c < 3; ++c) {
        albedo[c] = f.baseColor[c].at(x, y) * (1.0f - m);
        if (f.customData[0].data) {
            const float cd = f.customData[c].at(x, y);
            const float extra = cd * cd;  // CustomData holds √colour (§1.7)
            if (model == kSubsurface || model == kPreintegratedSkin || model == kTwoSidedFoliage)
                albedo[c] += extra;
            else if (model == kCloth)
                albedo[c] += extra * f.customData[3].at(x, y);
        }
    }
}

/// Work counted per pixel, in this order.
enum Counter { kComposited, kSkipped, kCounterCount };

/// One full-resolution pixel: unlit untouched, else SceneColor × AO + DiffuseColor × SSGI.
FP_HD inline void compositePixel(const Frame& f, int x, int y, unsigned long long* counts) {
    const int model = truncToInt(f.shadingModel.at(x, y), 0, 255);
    const float rgb[3] = {f.sceneColor[0].at(x, y), f.sceneColor[1].at(x, y),
                          f.sceneColor[2].at(x, y)};
    if (model == kUnlit) {  // AOMask = 0 and no diffuse: colour is untouched
        for (int c = 0; c < 3; ++c)
            f.out[c].at(x, y) = rgb[c];
        ++counts[kSkipped];
        return;
    }
    ++counts[kComposited];
    // algorithms §7.1: FinalAO = lerp(1, GBufferAO × DynamicAO, staticFraction).
    const float dyn = f.dynamicAO.at(f.half ? x / 2 : x, f.half ? y / 2 : y);
    const float finalAO = 1.0f + (f.gbufferAO.at(x, y) * dyn - 1.0f) * f.aoStaticFraction;
    float e[3], albedo[3];
    sampleSsgi(f, x, y, e);
    diffuseAlbedo(f, model, x, y, albedo);
    for (int c = 0; c < 3; ++c)
        f.out[c].at(x, y) = rgb[c] * finalAO + albedo[c] * e[c];
}

/// The whole pass on either backend (PerPixel.h).
template <class Ports, class Pixels>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, bool ue5,
         float aoStaticFraction) {
    Frame f{};
    const auto& sceneColor = ports.input(kSceneColor)->image();
    const auto& ssgi = ports.input(kDiffuse)->image();
    f.width = sceneColor.width();
    f.height = sceneColor.height();
    const int W = f.width, H = f.height, TW = ssgi.width(), TH = ssgi.height();
    f.half = TW < W || TH < H;
    FP_CHECK(TW == (f.half ? (W + 1) / 2 : W) && TH == (f.half ? (H + 1) / 2 : H),
             "the SSGI input is {}×{}: neither the frame's {}×{} nor half of it", TW, TH, W, H);
    f.depthTested = ue5;
    f.aoStaticFraction = aoStaticFraction;
    const auto& baseColor = ports.input(gbuffer::kBaseColor)->image();
    auto& out = ports.overwrite(kColor, {{W, H}});
    for (int c = 0; c < 3; ++c) {
        f.sceneColor[c] = viewOf(sceneColor.plane(c));
        f.ssgi[c] = viewOf(ssgi.plane(c));
        f.baseColor[c] = viewOf(baseColor.plane(c));
        f.out[c] = spanOf(out.image().plane(c));
    }
    f.shadingModel = viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0));
    f.gbufferAO = viewOf(ports.input(gbuffer::kGBufferAO)->image().plane(0));
    f.dynamicAO = viewOf(ports.input(kAo)->image().plane(0));
    f.metallic = viewOf(ports.input(gbuffer::kMetallic)->image().plane(0));
    if (ue5) {
        const auto& customData = ports.input(gbuffer::kCustomData)->image();
        for (int c = 0; c < 4; ++c)
            f.customData[c] = viewOf(customData.plane(c));
        f.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
        f.cam = ctx.frame().camera.current;
    }
    const auto counts = pixels.template forEach<kCounterCount>(
        W, H,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& c) { compositePixel(f, x, y, c.value); },
        "diffuse_indirect_composite");
    ctx.addWork("pixels", counts[kComposited]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
}

}  // namespace fp::composite
