#pragma once
// Direct lighting of one decoded GBuffer pixel by one light, per shading model, as Unreal 4.27's
// deferred lights evaluate it (ShadingModels.ush, algorithms §9.6): a surface part (diffuse and
// specular, both already × NoL) and a transmission part that is not × NoL, because it models
// light arriving through the surface from the far side. The caller multiplies each term by the
// light's falloff colour and its own shadowing (the transmission term takes the subsurface
// shadow, algorithms §9.3).
#include "foundation/ExpLog.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/ShadingModel.h"
#include "shading/BRDF.h"
#include "shading/PreintegratedSkinLut.h"

namespace fp {

/// One GBuffer pixel, decoded.
struct BxDFSurface {
    int shadingModel;                   //!< algorithms §1.6 ids (ShadingModelId)
    Vec3f N;                            //!< unit world normal
    Vec3f diffuseColor, specularColor;  //!< as SurfaceBRDF: BaseColor·(1 − Metallic), F0
    float roughness;                    //!< perceptual roughness [0, 1]
    Vec3f subsurfaceColor;              //!< CustomData.rgb² for 2, 3, 6; FuzzColor for cloth (8)
    float opacity;                      //!< CustomData.a for 2, 3, 6; cloth amount for 8
    float clearCoat = 0, clearCoatRoughness = 0;  //!< CustomData.r / .g for clear coat (4)
    float gbufferAO = 1;                          //!< GBuffer material AO [0, 1]
};

/// Each term per unit light falloff colour (irradiance at normal incidence); the surface terms
/// already carry NoL, the transmission term does not. T: float, or a SIMD vector of pixels
/// (foundation/LaneFloat.h) for the default-lit lobe.
template <class T>
struct BxDFTermsT {
    Vec3T<T> diffuse, specular, transmission;
};
using BxDFTerms = BxDFTermsT<float>;

/// The light a pixel takes from one direction: the terms × the falloff colour, the surface terms
/// dimmed by the surface shadow and transmission by the transmission shadow (algorithms §9.5).
template <class T>
FP_HD Vec3T<T> shadowedLight(const BxDFTermsT<T>& b, T surfaceShadow, T transmissionShadow, const Vec3T<T>& falloff) {
    return ((b.diffuse + b.specular) * surfaceShadow + b.transmission * transmissionShadow) * falloff;
}

namespace bxdf_detail {

// The angles every lobe needs, with the guards that keep them finite.
template <class T>
struct GeometryT {
    T NoL;  // dot(N, L), unclamped: transmission terms need its sign
    T NoV;  // ≥ 1e-4: views at or below the horizon still give finite lobes
    T NoH, VoH;
    // Zero when V = −L (our normalize of a zero vector), which keeps NoH and VoH at 0 where
    // HLSL's normalize would give NaN.
    Vec3T<T> H;
};
using Geometry = GeometryT<float>;

template <class T>
FP_HD GeometryT<T> geometryOf(const Vec3T<T>& N, const Vec3T<T>& V, const Vec3T<T>& L) {
    GeometryT<T> g;
    g.NoL = dot(N, L);
    // As SurfaceBRDF, so the lighting passes agree with the capture renderer. Unreal 4.27 takes
    // saturate(|N·V| + 1e-5) instead (inferred from memory of DefaultLitBxDF); they differ only
    // for back-facing views.
    const T NoV = dot(N, V);
    g.NoV = ifThenElse(NoV < 1e-4f, T(1e-4f), NoV);  // std::max's choice, NaN included
    g.H = normalize(V + L);
    g.NoH = saturate(dot(N, g.H));
    g.VoH = saturate(dot(V, g.H));
    return g;
}

// α = roughness², a2 = α², with roughness held off 0 as for every analytic light (BRDF.h).
template <class T>
FP_HD T lightA2(T roughness) {
    return pow4(ifThenElse(roughness < kMinLightRoughness, T(kMinLightRoughness), roughness));
}

// GGX specular × NoL, Unreal's default-lit lobe, with the terms the capture renderer uses (BRDF.h).
template <class T>
FP_HD Vec3T<T> ggxSpecular(const Vec3T<T>& specularColor, T roughness, const GeometryT<T>& g, T NoL) {
    const T a2 = lightA2(roughness);
    return schlickF(specularColor, g.VoH) *
           (ggxD(a2, g.NoH) * smithJointApproxVis(a2, g.NoV, NoL) * NoL);
}

// The default-lit surface terms, which every lit model starts from: zero where L is below the
// surface (NoL ≤ 0).
template <class T>
FP_HD BxDFTermsT<T> defaultLitLobe(const Vec3T<T>& diffuseColor, const Vec3T<T>& specularColor, T roughness,
                                   const GeometryT<T>& g) {
    BxDFTermsT<T> t;
    const auto lit = !(g.NoL <= 0.0f);
    if (!anyLane(lit))
        return t;
    t.diffuse = ifThenElse(lit, diffuseColor * (g.NoL / kPiF), Vec3T<T>{});
    t.specular = ifThenElse(lit, ggxSpecular(specularColor, roughness, g, g.NoL), Vec3T<T>{});
    return t;
}

FP_HD inline BxDFTerms defaultLit(const BxDFSurface& s, const Geometry& g) {
    return defaultLitLobe(s.diffuseColor, s.specularColor, s.roughness, g);
}

// algorithms §9.6 subsurface (2): wrap-around back scatter plus a forward in-scatter lobe towards
// the viewer, lerped so the sum never exceeds the lobe.
FP_HD inline Vec3f subsurfaceTransmission(const BxDFSurface& s,
                             const Vec3f& V,
                             const Vec3f& L,
                             const Geometry& g) {
    const float forward = saturate(-dot(L, V));
    const float inScatter = powFloat(forward, 12.0f) * (3.0f + (0.1f - 3.0f) * s.opacity);
    const float normalTerm = saturate(dot(s.N, g.H) * s.opacity + 1.0f - s.opacity);
    const float backScatter = s.gbufferAO * normalTerm / (2.0f * kPiF);
    return s.subsurfaceColor * (backScatter + (1.0f - backScatter) * inScatter);
}

// algorithms §9.6 preintegrated skin (3): the LUT row is 1 − Opacity.
FP_HD inline Vec3f skinTransmission(const BxDFSurface& s, const Geometry& g, const PreintegratedSkinView& skin) {
    const Vec3f lut = skin.sample(saturate(g.NoL * 0.5f + 0.5f), 1.0f - s.opacity);
    return lut * s.subsurfaceColor;
}

// algorithms §9.6 two-sided foliage (6): wrapped back lighting (wrap 0.5, normalised by
// (1 + wrap)²) times a fixed GGX lobe (a2 = 0.36) around the view-through direction.
FP_HD inline Vec3f foliageTransmission(const BxDFSurface& s, const Vec3f& V, const Vec3f& L, const Geometry& g) {
    const float wrapNoL = saturate((-g.NoL + 0.5f) / 2.25f);
    const float scatter = ggxD(0.36f, saturate(-dot(V, L)));
    return s.subsurfaceColor * (wrapNoL * scatter);
}

// Clear coat (4), inferred simplification of Unreal's ClearCoatBxDF: a grey GGX coat lobe
// (F0 = 0.04, IOR 1.5) scaled by ClearCoat over the default-lit base, the base dimmed by the
// light the coat reflects. Omitted from Unreal: refracting V and L into the coat (the base lobe
// then sees sharper, shifted angles), the coat's absorption/tinting of the base along those
// refracted path lengths, attenuating both on the way in and out, and the optional bottom normal
// (CLEAR_COAT_BOTTOM_NORMAL).
FP_HD inline BxDFTerms clearCoat(const BxDFSurface& s, const Geometry& g) {
    BxDFTerms t = defaultLit(s, g);
    if (g.NoL <= 0.0f)
        return t;
    const float fc = pow5(1.0f - g.VoH);
    const float coatF = (fc + (1.0f - fc) * 0.04f) * s.clearCoat;
    const float a2 = lightA2(s.clearCoatRoughness);
    const float coat = coatF * ggxD(a2, g.NoH) * smithJointApproxVis(a2, g.NoV, g.NoL) * g.NoL;
    const float base = 1.0f - coatF;
    t.diffuse = t.diffuse * base;
    t.specular = t.specular * base + Vec3f{coat, coat, coat};
    return t;
}

// Cloth (8): the GGX lobe blended towards an asperity-scattering lobe by the cloth amount. Both
// helpers below are inferred (the reference is silent on cloth): D_InvGGX is an "inverted" GGX
// that peaks at grazing half vectors (the fuzz rim), Vis_Cloth is Neubelt & Pettineo's
// visibility for cloth, 1/(4(NoL + NoV − NoL·NoV)).
FP_HD inline float invGgxD(float a2, float NoH) {
    const float d = (NoH - a2 * NoH) * NoH + a2;
    return (1.0f + 4.0f * a2 * a2 / (d * d)) / (kPiF * (1.0f + 4.0f * a2));
}

FP_HD inline float clothVis(float NoV, float NoL) {
    return 1.0f / (4.0f * (NoL + NoV - NoL * NoV));
}

FP_HD inline BxDFTerms cloth(const BxDFSurface& s, const Geometry& g) {
    BxDFTerms t = defaultLit(s, g);
    if (g.NoL <= 0.0f)
        return t;
    const float a2 = lightA2(s.roughness);
    const Vec3f fuzz =
        schlickF(s.subsurfaceColor, g.VoH) * (invGgxD(a2, g.NoH) * clothVis(g.NoV, g.NoL) * g.NoL);
    const float amount = saturate(s.opacity);
    t.specular = t.specular * (1.0f - amount) + fuzz * amount;
    return t;
}

}  // namespace bxdf_detail

/// True for the shading models evaluateBxDF lights with the default-lit lobe alone (no
/// transmission, no lobe of their own): what deferred_lighting's SIMD lanes may shade.
FP_HD inline bool isDefaultLitLobe(int model) {
    switch (model) {
        case kUnlit:
        case kSubsurface:
        case kPreintegratedSkin:
        case kClearCoat:
        case kTwoSidedFoliage:
        case kCloth:
            return false;
        default:
            // Default lit, and the stand-in for subsurface profile (5), hair (7), eye (9) and
            // later ids: Burley diffuse with the profile's dual specular, the hair BSDF and the
            // eye's iris model are not transcribed (algorithms §13 gaps 3–4).
            return true;
    }
}

/// Reflected (diffuse, specular) and transmitted radiance towards unit V from a light in unit
/// direction L. Zero surface terms when L is below the surface (N·L ≤ 0); always finite, also for
/// V at or below the horizon. `skin` is the preintegrated-skin table where the pixels run.
FP_HD inline BxDFTerms evaluateBxDF(const BxDFSurface& s, const Vec3f& V, const Vec3f& L,
                                    const PreintegratedSkinView& skin) {
    using namespace bxdf_detail;
    if (s.shadingModel == kUnlit)
        return {};
    const Geometry g = geometryOf(s.N, V, L);
    if (isDefaultLitLobe(s.shadingModel))
        return defaultLit(s, g);
    switch (s.shadingModel) {
        case kSubsurface: {
            BxDFTerms t = defaultLit(s, g);
            t.transmission = subsurfaceTransmission(s, V, L, g);
            return t;
        }
        case kPreintegratedSkin: {
            BxDFTerms t = defaultLit(s, g);
            t.transmission = skinTransmission(s, g, skin);
            return t;
        }
        case kClearCoat:
            return clearCoat(s, g);
        case kTwoSidedFoliage: {
            BxDFTerms t = defaultLit(s, g);
            t.transmission = foliageTransmission(s, V, L, g);
            return t;
        }
        case kCloth:
            return cloth(s, g);
        default:  // not reached: isDefaultLitLobe took every other model
            return defaultLit(s, g);
    }
}

/// evaluateBxDF with the process's preintegrated-skin table (on the host).
inline BxDFTerms evaluateBxDF(const BxDFSurface& s, const Vec3f& V, const Vec3f& L) {
    return evaluateBxDF(s, V, L, PreintegratedSkinLut::instance().view());
}

}  // namespace fp
