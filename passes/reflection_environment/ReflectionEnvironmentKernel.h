#pragma once
// ReflectionEnvironment + SkyLighting's per-pixel work (algorithms §8), written once for both
// backends: ReflectionEnvironmentPass::execute runs it with CpuPixels, its .cu file with
// CudaPixels. The sky's cube, the captures' cubes and the EnvBRDF table are the pass's host
// objects; on the GPU they are read from copies made for the frame (PassPorts' constants).
#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/ExpLog.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Sampling.h"
#include "foundation/ShadingModel.h"
#include "framework/Pass.h"
#include "screenspace/GBuffer.h"
#include "screenspace/MaterialViews.h"
#include "shading/BRDF.h"
#include "shading/Cubemap.h"
#include "shading/EnvBRDF.h"
#include "shading/ReflectionCaptures.h"
#include "shading/SphericalHarmonics.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace fp::reflection_environment {

// Ports (besides the GBuffer's, gbuffer::k*).
inline constexpr const char* kColor = "color";
inline constexpr const char* kReflection = "reflection";
inline constexpr const char* kAo = "ao";
inline constexpr const char* kSpecular = "specular";
inline constexpr const char* kDiffuse = "diffuse";

// Unreal's F0 for the clear coat's own interface (algorithms §8.2 step 8).
constexpr float kCoatF0 = 0.04f;

/// Work counted per pixel, in this order.
enum Counter { kLit, kSkipped, kEmpty, kCounterCount };

/// Lagarde's specular occlusion, saturate((NoV + AO)^(roughness²) − 1 + AO) (§8.2 step 5); the
/// power through ExpLog.h, so both backends give the same bits.
FP_HD inline float specularOcclusion(float NoV, float ao, float roughness) {
    return saturate(powFloat(NoV + ao, roughness * roughness) - 1.0f + ao);
}

// NaN and negatives to 0 (§8.2 step 9).
FP_HD inline Vec3f finiteNonNegative(const Vec3f& c) {
    auto f = [](float v) { return v > 0.0f && v < std::numeric_limits<float>::infinity() ? v : 0.0f; };
    return {f(c.x), f(c.y), f(c.z)};
}

// The off-specular peak (§8.2 step 2): rough lobes lean from the mirror direction towards N.
FP_HD inline Vec3f dominantDirection(const Vec3f& N, const Vec3f& R, float roughness) {
    const float a = roughness * roughness;
    const float t = (1.0f - a) * (std::sqrt(1.0f - a) + a);
    return normalize(N * (1.0f - t) + R * t);
}

/// Everything one frame's pixels read and write. Absent images have null data.
struct Frame {
    CameraView cam;
    PlaneView in[3], ssr[4], ao;
    MaterialViews m;
    bool halfAo;
    PlaneSpan out[3], specOut[3], diffOut[3];
    bool doSpecular, doDiffuse, useSpecularOcclusion;
    bool sky;  //!< a sky light: its cube, its SH and its occlusion tint are bound
    CubemapView skyCube;
    SH3 skySh;
    Vec3f occlusionTint;
    const PreparedCapture* captures;
    int captureCount;
    EnvBRDFView lut;
};

FP_HD inline Vec3f rgbAt(const PlaneView (&p)[3], int x, int y) {
    return {p[0].at(x, y), p[1].at(x, y), p[2].at(x, y)};
}

// The specular of one layer (§8.2 steps 2–6): SSR, then the captures and the sky in what it
// leaves, under specular occlusion. EnvBRDF is the caller's, since clear coat weighs its two
// layers apart.
FP_HD inline Vec3f layer(const Frame& f, const Vec3f& P, const Vec3f& N, const Vec3f& V, float NoV,
                         float roughness, const Vec3f& ssrColor, float ssrAlpha, float occlusionAO) {
    Vec3f color = ssrColor;
    float alpha = 1.0f - ssrAlpha;
    if (f.useSpecularOcclusion) alpha *= specularOcclusion(NoV, occlusionAO, roughness);
    if (alpha <= 0.0f || (!f.sky && f.captureCount == 0)) return color;
    const Vec3f R = dominantDirection(N, reflect(V, N), roughness);
    color += compositeCaptures(f.captures, f.captureCount, P, R, roughness, alpha);
    if (f.sky && alpha > 0.0f) color += f.skyCube.sample(R, f.skyCube.mipForRoughness(roughness)) * alpha;
    return color;
}

/// One pixel: the sky light's diffuse and the reflections added to its colour (unlit pixels and
/// the sky untouched), counted in `counts` (indexed by Counter).
FP_HD inline void environmentPixel(const Frame& f, int x, int y, unsigned long long* counts) {
    const Vec3f before = rgbAt(f.in, x, y);
    const double d = f.m.depth.at(x, y);
    const int model = truncToInt(f.m.shadingModel.at(x, y), 0, 255);
    const bool ssrEmpty = !f.ssr[0].data || (f.ssr[3].at(x, y) == 0.0f && f.ssr[0].at(x, y) == 0.0f &&
                                             f.ssr[1].at(x, y) == 0.0f && f.ssr[2].at(x, y) == 0.0f);
    Vec3f diffuse, spec;
    if (!isLitSurface(d, f.m.shadingModel.at(x, y))) {
        ++counts[kSkipped];
    } else if (!f.sky && f.captureCount == 0 && ssrEmpty) {
        // Without a sky or captures, a pixel the SSR left empty (rough, missed, faded) gets nothing.
        ++counts[kEmpty];
    } else {
        ++counts[kLit];
        const Vec3f N = normalize(rgbAt(f.m.normal, x, y));
        const Vec3d p = f.cam.translatedFromPixel(x, y, d);
        const Vec3f P{float(p.x), float(p.y), float(p.z)};
        const Vec3f V = normalize(-P);
        const Vec3f base = rgbAt(f.m.baseColor, x, y);
        const SurfaceBRDF brdf = SurfaceBRDF::fromMaterial(base, f.m.metallic.at(x, y), f.m.specular.at(x, y),
                                                           f.m.roughness.at(x, y));
        Vec3f cd;
        float cdA = 0.0f;
        if (f.m.customData[0].data) {
            cd = {f.m.customData[0].at(x, y), f.m.customData[1].at(x, y), f.m.customData[2].at(x, y)};
            cdA = f.m.customData[3].at(x, y);
        }
        const float materialAO = f.m.gbufferAO.data ? f.m.gbufferAO.at(x, y) : 1.0f;
        const float screenAO = f.ao.data ? f.ao.at(f.halfAo ? x / 2 : x, f.halfAo ? y / 2 : y) : 1.0f;
        if (f.doDiffuse) {
            // §8.1: sky visibility 1 (no distance-field AO), combined with the AO by Minimum;
            // subsurface-type colours are stored as √colour (§1.7).
            const float s = materialAO < screenAO ? materialAO : screenAO;
            Vec3f albedo = model == kSubsurfaceProfile || model == kEye ? base : brdf.diffuseColor;
            const Vec3f extra = cd * cd;
            if (model == kSubsurface || model == kPreintegratedSkin) albedo += extra;
            if (model == kCloth) albedo += extra * cdA;
            diffuse = (f.skySh.diffuse(N) * s + f.occlusionTint * (1.0f - s)) * albedo;
            if (model == kTwoSidedFoliage) diffuse += f.skySh.diffuse(-N) * extra * s;
        }
        if (f.doSpecular && model != kHair) {
            const float NoV = saturate(dot(N, V));
            const float roughness = brdf.roughness;
            const float occlusionAO = materialAO * screenAO;
            Vec3f ssrColor;
            float ssrAlpha = 0.0f;
            if (f.ssr[0].data) {
                ssrColor = {f.ssr[0].at(x, y), f.ssr[1].at(x, y), f.ssr[2].at(x, y)};
                ssrAlpha = saturate(f.ssr[3].at(x, y));
            }
            const EnvBRDFTerms terms = f.lut.lookup(NoV, roughness);
            if (model == kClearCoat && f.m.customData[0].data) {
                // §8.2 steps 4 and 8: the base loses the SSR to the coat and its grazing term,
                // and sees what the coat's Fresnel lets through.
                const float coat = saturate(cd.x), coatRoughness = saturate(cd.y);
                const Vec3f baseLayer = layer(f, P, N, V, NoV, roughness, ssrColor * (1.0f - coat),
                                              ssrAlpha * (1.0f - coat), occlusionAO);
                const Vec3f baseBrdf = applyEnvBRDF(brdf.specularColor, {terms.a, terms.b * (1.0f - coat)});
                const EnvBRDFTerms coatTerms = f.lut.lookup(NoV, coatRoughness);
                const float coatF = (kCoatF0 * coatTerms.a + coatTerms.b) * coat;
                spec = baseLayer * baseBrdf * (1.0f - coatF) +
                       layer(f, P, N, V, NoV, coatRoughness, ssrColor, ssrAlpha, occlusionAO) * coatF;
            } else {
                spec = layer(f, P, N, V, NoV, roughness, ssrColor, ssrAlpha, occlusionAO) *
                       applyEnvBRDF(brdf.specularColor, terms);
            }
        }
    }
    diffuse = finiteNonNegative(diffuse);
    spec = finiteNonNegative(spec);
    const Vec3f after = before + diffuse + spec;
    for (int c = 0; c < 3; ++c) {
        f.out[c].at(x, y) = after[c];
        if (f.specOut[c]) f.specOut[c].at(x, y) = spec[c];
        if (f.diffOut[c]) f.diffOut[c].at(x, y) = diffuse[c];
    }
}

/// What lights the reflections this frame, made on the host by the pass (its caches).
struct Lighting {
    bool reflections, skyDiffuse, specularOcclusion;  //!< the pass's parameters
    const Cubemap* skyCube = nullptr;                 //!< null without a sky light
    SH3 skySh;
    Vec3f occlusionTint;
    std::vector<PreparedCapture> captures;   //!< host views, ascending radius
    std::vector<const Cubemap*> captureCubes;  //!< the cube each of `captures` reads
};

/// The whole pass through `ports` (HostPorts or DevicePorts) on `pixels` (CpuPixels or
/// CudaPixels), its work reported to `ctx`.
template <class Ports, class Pixels>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const Lighting& lighting) {
    const auto& in = ports.input(kColor)->image();
    const int W = in.width(), H = in.height();
    const std::vector<Extent> frameExtent = {{W, H}};
    Frame f{};
    auto& out = ports.overwrite(kColor, frameExtent);
    for (int c = 0; c < 3; ++c) {
        f.in[c] = viewOf(in.plane(c));
        f.out[c] = spanOf(out.image().plane(c));
    }
    if (auto* specOut = ports.overwriteIfRequested(kSpecular, frameExtent))
        for (int c = 0; c < 3; ++c) f.specOut[c] = spanOf(specOut->image().plane(c));
    if (auto* diffOut = ports.overwriteIfRequested(kDiffuse, frameExtent))
        for (int c = 0; c < 3; ++c) f.diffOut[c] = spanOf(diffOut->image().plane(c));

    const auto* ssr = ports.input(kReflection);
    f.sky = lighting.skyCube != nullptr;
    f.doSpecular = lighting.reflections && (f.sky || ssr || !lighting.captures.empty());
    f.doDiffuse = lighting.skyDiffuse && f.sky;
    if (!f.doSpecular && !f.doDiffuse) {
        // Nothing lights the reflections: the colour passes through and no GBuffer is read.
        pixels.template forEach<0>(
            W, H,
            [=] FP_HD(int x, int y, WorkCounts<0>&) {
                for (int c = 0; c < 3; ++c) {
                    f.out[c].at(x, y) = f.in[c].at(x, y);
                    if (f.specOut[c]) f.specOut[c].at(x, y) = 0.0f;
                    if (f.diffOut[c]) f.diffOut[c].at(x, y) = 0.0f;
                }
            },
            "reflection_environment copy");
        ctx.addWork("skippedPixels", uint64_t(W) * H);
        return;
    }
    f.cam = ctx.frame().camera.current;
    f.useSpecularOcclusion = lighting.specularOcclusion;
    f.m = bindMaterialViews(ports);
    if (ssr) {
        const auto& image = ssr->image();
        FP_CHECK(image.width() == W && image.height() == H, "the reflection input is {}×{}, the frame {}×{}",
                 image.width(), image.height(), W, H);
        for (int c = 0; c < 4; ++c) f.ssr[c] = viewOf(image.plane(c));
    }
    if (const auto* ao = ports.input(kAo)) {
        const auto& image = ao->image();
        f.halfAo = image.width() < W || image.height() < H;
        FP_CHECK(image.width() == (f.halfAo ? (W + 1) / 2 : W) && image.height() == (f.halfAo ? (H + 1) / 2 : H),
                 "the AO input is {}×{}: neither the frame's {}×{} nor half of it", image.width(),
                 image.height(), W, H);
        f.ao = viewOf(image.plane(0));
    }

    // The tables the pixels read, where the pixels run (the GPU reads copies).
    const EnvBRDFLut& lut = EnvBRDFLut::instance();
    const auto lutTexels = ports.constants(lut.texels().data(), lut.texels().size());
    f.lut = {lutTexels.get()};
    std::vector<std::shared_ptr<const Vec3f>> cubeTexels;  // alive until the pixels are done
    auto placed = [&](const Cubemap& cube) {
        cubeTexels.push_back(ports.constants(cube.texels().data(), cube.texels().size()));
        return cube.view().rebased(cube.texels().data(), cubeTexels.back().get());
    };
    if (f.sky) {
        f.skyCube = placed(*lighting.skyCube);
        f.skySh = lighting.skySh;
        f.occlusionTint = lighting.occlusionTint;
    }
    std::vector<PreparedCapture> captures = lighting.captures;
    for (std::size_t i = 0; i < captures.size(); ++i) captures[i].cube = placed(*lighting.captureCubes[i]);
    const auto captureArray = ports.constants(captures.data(), captures.size());
    f.captures = captureArray.get();
    f.captureCount = lighting.reflections ? int(captures.size()) : 0;

    const auto counts = pixels.template forEach<kCounterCount>(
        W, H, [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& n) { environmentPixel(f, x, y, n.value); },
        "reflection_environment");
    ctx.addWork("pixels", counts[kLit]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
    ctx.addWork("emptyPixels", counts[kEmpty]);
}

}  // namespace fp::reflection_environment
