#include "shading/ShadingModelBxDF.h"

#include "foundation/ShadingModel.h"
#include "shading/BRDF.h"
#include "shading/PreintegratedSkinLut.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

// The angles every lobe needs, with the guards that keep them finite.
struct Geometry {
    float NoL;  // dot(N, L), unclamped: transmission terms need its sign
    float NoV;  // ≥ 1e-4: views at or below the horizon still give finite lobes
    float NoH, VoH;
    // Zero when V = −L (our normalize of a zero vector), which keeps NoH and VoH at 0 where
    // HLSL's normalize would give NaN.
    Vec3f H;
};

Geometry geometryOf(const Vec3f& N, const Vec3f& V, const Vec3f& L) {
    Geometry g;
    g.NoL = dot(N, L);
    // As SurfaceBRDF, so the lighting passes agree with the capture renderer. Unreal 4.27 takes
    // saturate(|N·V| + 1e-5) instead (inferred from memory of DefaultLitBxDF); they differ only
    // for back-facing views.
    g.NoV = std::max(dot(N, V), 1e-4f);
    g.H = normalize(V + L);
    g.NoH = std::clamp(dot(N, g.H), 0.0f, 1.0f);
    g.VoH = std::clamp(dot(V, g.H), 0.0f, 1.0f);
    return g;
}

// α = roughness², a2 = α², with roughness held off 0 as for every analytic light (BRDF.h).
float lightA2(float roughness) {
    return pow4(std::max(roughness, kMinLightRoughness));
}

// GGX specular × NoL, Unreal's default-lit lobe, with the terms the capture renderer uses (BRDF.h).
Vec3f ggxSpecular(const Vec3f& specularColor, float roughness, const Geometry& g, float NoL) {
    const float a2 = lightA2(roughness);
    return schlickF(specularColor, g.VoH) *
           (ggxD(a2, g.NoH) * smithJointApproxVis(a2, g.NoV, NoL) * NoL);
}

// The default-lit surface terms, which every lit model starts from.
BxDFTerms defaultLit(const BxDFSurface& s, const Geometry& g) {
    BxDFTerms t;
    if (g.NoL <= 0.0f)
        return t;
    t.diffuse = s.diffuseColor * (g.NoL / kPiF);
    t.specular = ggxSpecular(s.specularColor, s.roughness, g, g.NoL);
    return t;
}

// algorithms §9.6 subsurface (2): wrap-around back scatter plus a forward in-scatter lobe towards
// the viewer, lerped so the sum never exceeds the lobe.
Vec3f subsurfaceTransmission(const BxDFSurface& s,
                             const Vec3f& V,
                             const Vec3f& L,
                             const Geometry& g) {
    const float forward = saturate(-dot(L, V));
    const float inScatter = std::pow(forward, 12.0f) * (3.0f + (0.1f - 3.0f) * s.opacity);
    const float normalTerm = saturate(dot(s.N, g.H) * s.opacity + 1.0f - s.opacity);
    const float backScatter = s.gbufferAO * normalTerm / (2.0f * kPiF);
    return s.subsurfaceColor * (backScatter + (1.0f - backScatter) * inScatter);
}

// algorithms §9.6 preintegrated skin (3): the LUT row is 1 − Opacity.
Vec3f skinTransmission(const BxDFSurface& s, const Geometry& g) {
    const Vec3f lut =
        PreintegratedSkinLut::instance().sample(saturate(g.NoL * 0.5f + 0.5f), 1.0f - s.opacity);
    return lut * s.subsurfaceColor;
}

// algorithms §9.6 two-sided foliage (6): wrapped back lighting (wrap 0.5, normalised by
// (1 + wrap)²) times a fixed GGX lobe (a2 = 0.36) around the view-through direction.
Vec3f foliageTransmission(const BxDFSurface& s, const Vec3f& V, const Vec3f& L, const Geometry& g) {
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
BxDFTerms clearCoat(const BxDFSurface& s, const Geometry& g) {
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
float invGgxD(float a2, float NoH) {
    const float d = (NoH - a2 * NoH) * NoH + a2;
    return (1.0f + 4.0f * a2 * a2 / (d * d)) / (kPiF * (1.0f + 4.0f * a2));
}

float clothVis(float NoV, float NoL) {
    return 1.0f / (4.0f * (NoL + NoV - NoL * NoV));
}

BxDFTerms cloth(const BxDFSurface& s, const Geometry& g) {
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

}  // namespace

bool isDefaultLitLobe(int model) {
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

BxDFTerms evaluateBxDF(const BxDFSurface& s, const Vec3f& V, const Vec3f& L) {
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
            t.transmission = skinTransmission(s, g);
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

}  // namespace fp
