#pragma once
// deferred_lighting's per-pixel work (algorithms §9.5–9.6), written once: DeferredLightingPass's
// tile loop runs it pixel by pixel on the CPU, DeferredLightingPass.cu once a thread on the GPU,
// and for default-lit pixels of a rect light rectDefaultLit runs a SIMD vector of neighbouring
// pixels at a time (DeferredLightingLanes.cpp instantiates it over foundation/LaneFloat.h), the
// same operations lane by lane, so the same bits.
#include "foundation/Camera.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/PlaneView.h"
#include "foundation/Scene.h"
#include "foundation/ShadingModel.h"
#include "framework/Pass.h"
#include "screenspace/GBuffer.h"
#include "screenspace/MaterialViews.h"
#include "shading/BRDF.h"
#include "shading/LightAttenuation.h"
#include "shading/PreintegratedSkinLut.h"
#include "shading/ShadingModelBxDF.h"

#include <cmath>

namespace fp::deferred_lighting {

inline constexpr const char* kColor = "color";
inline constexpr const char* kAttenuation = "attenuation";

/// Work counted per pixel, in this order.
enum Counter { kLit, kSkipped, kCounterCount };

/// The light as per-pixel code reads it, relative to the eye so a camera far from the origin
/// loses nothing. A rect light is an N×N grid of cell centres (row j outer, column i inner).
struct LightShape {
    LightType type;
    Vec3f position, axis, color;  //!< axis: the direction the light travels
    double attenuationRadius;     //!< local lights: no light beyond it (0 = unlimited)
    float cosOuter, cosInner;     //!< spot lights: the cone
    const Vec3f* rectPoints;
    int rectCount;
    Vec3f rectNormal;
    float rectCellArea;
};

/// Everything one frame's pixels read and write. Absent images have null data.
struct Frame {
    CameraView cam;
    LightShape light;
    PlaneView color[3], attenuation[4];
    MaterialViews m;
    PlaneSpan out[3];
    PreintegratedSkinView skin;
};

/// A pixel as every path starts it: its scene colour and, on a lit surface, its model and
/// camera-relative position.
struct PixelStart {
    Vec3f color;
    bool lit = false;
    int model = 0;
    Vec3f p;
};

FP_HD inline PixelStart startPixel(const Frame& f, int x, int y) {
    PixelStart s;
    s.color = {f.color[0].at(x, y), f.color[1].at(x, y), f.color[2].at(x, y)};
    const double d = f.m.depth.at(x, y);
    s.model = truncToInt(f.m.shadingModel.at(x, y), 0, 255);
    s.lit = isLitSurface(d, f.m.shadingModel.at(x, y));
    if (s.lit) s.p = Vec3f(f.cam.translatedFromPixel(x, y, d));
    return s;
}

/// The BxDF inputs of pixel (x, y) from its GBuffer.
FP_HD inline BxDFSurface materialAt(const Frame& f, int model, int x, int y) {
    BxDFSurface s{};
    s.shadingModel = model;
    s.N = normalize(Vec3f{f.m.normal[0].at(x, y), f.m.normal[1].at(x, y), f.m.normal[2].at(x, y)});
    const Vec3f base{f.m.baseColor[0].at(x, y), f.m.baseColor[1].at(x, y), f.m.baseColor[2].at(x, y)};
    const SurfaceBRDF brdf = SurfaceBRDF::fromMaterial(base, f.m.metallic.at(x, y), f.m.specular.at(x, y),
                                                       f.m.roughness.at(x, y));
    s.diffuseColor = brdf.diffuseColor;
    s.specularColor = brdf.specularColor;
    s.roughness = brdf.roughness;
    if (f.m.customData[0].data) {
        // algorithms §1.7: subsurface-type colours are stored as √colour.
        const float r = f.m.customData[0].at(x, y), g = f.m.customData[1].at(x, y), b = f.m.customData[2].at(x, y),
                    a = f.m.customData[3].at(x, y);
        s.subsurfaceColor = {r * r, g * g, b * b};
        s.opacity = a;
        s.clearCoat = r;
        s.clearCoatRoughness = g;
    }
    s.gbufferAO = f.m.gbufferAO.data ? f.m.gbufferAO.at(x, y) : 1.0f;
    return s;
}

/// The surface and transmission shadows the light-attenuation buffer gives pixel (x, y) (1, 1
/// without one).
FP_HD inline void shadowsAt(const Frame& f, int x, int y, float& surfaceShadow, float& transmissionShadow) {
    surfaceShadow = transmissionShadow = 1.0f;
    if (f.attenuation[0].data) {
        const LightAttenuation la = LightAttenuation::load(f.attenuation, x, y);
        surfaceShadow = la.surfaceShadow(f.light.type);
        transmissionShadow = la.transmissionShadow(f.light.type);
    }
}

/// Calls `fn(L, falloff, inFront)` for each grid point of the rect light with the unit direction
/// from camera-relative p towards it and the unshadowed irradiance it brings at normal incidence,
/// where `inFront` (a mask: T is float or lanes of pixels) says which of the p see the emitting
/// side; points that no p sees are left out. Returns the mask of the p that saw any point.
template <class T, class Fn>
FP_HD auto forEachRectPoint(const LightShape& light, const Vec3T<T>& p, Fn&& fn) {
    const Vec3T<T> normal(light.rectNormal), color(light.color);
    decltype(p.x < p.x) reached{};
    for (int k = 0; k < light.rectCount; ++k) {
        const Vec3T<T> d = Vec3T<T>(light.rectPoints[k]) - p;
        const T dist2 = dot(d, d);
        const Vec3T<T> L = d / sqrtOf(dist2);
        const T cosL = -dot(L, normal);
        const auto inFront = !(cosL <= 0.0f);
        if (!anyLane(inFront)) continue;
        fn(L, color * (cosL * light.rectCellArea / dist2), inFront);
        reached = reached | inFront;
    }
    return reached;
}

/// A default-lit pixel as rectDefaultLit reads it (T: float, or lanes of pixels).
template <class T>
struct DefaultLitPixel {
    Vec3T<T> p, V, N, diffuseColor, specularColor;  // p camera-relative, V = normalize(−p)
    T roughness, surfaceShadow, transmissionShadow;
};

/// The default-lit BxDF of the pixels of `s` summed over the rect light's grid, each point's light
/// shadowed (shadowedLight) and added where the pixel sees it; `reached` says which pixels saw any
/// point. evaluateBxDF's default-lit case, as shadePixel sums it.
template <class T>
FP_HD Vec3T<T> rectDefaultLit(const LightShape& light, const DefaultLitPixel<T>& s, decltype(T() < T())& reached) {
    Vec3T<T> sum;
    reached = forEachRectPoint(light, s.p, [&](const Vec3T<T>& L, const Vec3T<T>& falloff, const auto& inFront) {
        const BxDFTermsT<T> b =
            bxdf_detail::defaultLitLobe(s.diffuseColor, s.specularColor, s.roughness, bxdf_detail::geometryOf(s.N, s.V, L));
        sum = ifThenElse(inFront, sum + shadowedLight(b, s.surfaceShadow, s.transmissionShadow, falloff), sum);
    });
    return sum;
}

/// Calls `fn(L, falloff)` for each direction towards the light that reaches camera-relative p,
/// with the unshadowed irradiance it brings at normal incidence: one, or the rect light's grid
/// points in front of the emitter. Returns how many (0: out of the light's reach).
template <class Fn>
FP_HD int forEachIncoming(const LightShape& light, const Vec3f& p, Fn&& fn) {
    if (light.type == LightType::Directional) {
        fn(-light.axis, light.color);
        return 1;
    }
    if (light.type == LightType::Rect) {
        int n = 0;
        forEachRectPoint(light, p, [&](const Vec3f& L, const Vec3f& falloff, bool) {
            fn(L, falloff);
            ++n;
        });
        return n;
    }
    const Vec3f d = light.position - p;
    const float dist2 = dot(d, d);
    if (light.attenuationRadius > 0.0 && dist2 > light.attenuationRadius * light.attenuationRadius) return 0;
    const Vec3f L = d / std::sqrt(dist2);
    // Inverse square, as the capture and the truth light it.
    const float mask = light.type == LightType::Spot
                           ? Light::spotMaskOf(dot(-L, light.axis), light.cosOuter, light.cosInner)
                           : 1.0f;
    const float falloff = mask / dist2;
    if (falloff <= 0.0f) return 0;
    fn(L, light.color * falloff);
    return 1;
}

/// Pixel (x, y) from its start: the light reflected and transmitted towards the eye added to its
/// colour (surface terms dimmed by the surface shadow, transmission by the transmission shadow,
/// algorithms §9.5), written out and counted.
FP_HD inline void shadePixel(const Frame& f, int x, int y, PixelStart s, unsigned long long* counts) {
    Vec3f sum;
    int n = 0;
    if (s.lit) {
        const BxDFSurface m = materialAt(f, s.model, x, y);
        float surfaceShadow, transmissionShadow;
        shadowsAt(f, x, y, surfaceShadow, transmissionShadow);
        const Vec3f V = normalize(-s.p);
        n = forEachIncoming(f.light, s.p, [&](const Vec3f& L, const Vec3f& falloff) {
            sum += shadowedLight(evaluateBxDF(m, V, L, f.skin), surfaceShadow, transmissionShadow, falloff);
        });
    }
    if (n == 0) {
        ++counts[kSkipped];  // sky, unlit, or out of the light's reach: colour unchanged
    } else {
        ++counts[kLit];
        s.color += sum;
    }
    for (int c = 0; c < 3; ++c) f.out[c].at(x, y) = s.color[c];
}

/// The frame as the pixels read it, through `ports` (HostPorts or DevicePorts): `points` holds
/// the rect light's grid (camera-relative) where the pixels run, `skin` the skin table.
template <class Ports>
Frame bindFrame(const Ports& ports, const FrameInfo& frame, const LightShape& light, const Vec3f* points,
                const PreintegratedSkinView& skin) {
    Frame f{};
    f.cam = frame.camera.current;
    f.light = light;
    f.light.rectPoints = points;
    f.skin = skin;
    const auto& color = ports.input(kColor)->image();
    auto& out = ports.overwrite(kColor, {frame.extent});
    for (int c = 0; c < 3; ++c) {
        f.color[c] = viewOf(color.plane(c));
        f.out[c] = spanOf(out.image().plane(c));
    }
    f.m = bindMaterialViews(ports);
    if (const auto* attenuation = ports.input(kAttenuation))
        for (int c = 0; c < 4; ++c) f.attenuation[c] = viewOf(attenuation->image().plane(c));
    return f;
}

}  // namespace fp::deferred_lighting
