#include "reference/ScatterLobe.h"

#include "foundation/Sampling.h"

#include <algorithm>

namespace fp {

ScatterLobe::ScatterLobe(Kind kind, const SurfacePoint& s) : mKind(kind), mS(s) {
    mNoV = dot(s.normal, s.toViewer);
    // The α BRDF.h evaluates with (roughness clamped for light sources), so f/pdf stays
    // consistent down to roughness 0.
    const float r = std::max(s.brdf.roughness, kMinLightRoughness);
    mAlpha = r * r;
    mA2 = mAlpha * mAlpha;
    const bool specular = 50.0f * s.brdf.specularColor.y > 0.0f && mNoV > 0.0f;  // Unreal's 2% cut
    switch (kind) {
    case Kind::Cosine: break;
    case Kind::Specular: mActive = specular; break;
    case Kind::Bsdf: {
        const float d = luminance(s.brdf.diffuseColor);
        const float sp = specular ? luminance(schlickF(s.brdf.specularColor, mNoV)) : 0.0f;
        mActive = mNoV > 0.0f && d + sp > 0.0f;
        // Lobe choice in proportion to albedo, kept away from 0 and 1 so neither lobe starves.
        mSpecularProbability = mActive ? sp / (d + sp) : 0.0f;
        if (d > 0.0f && sp > 0.0f) mSpecularProbability = std::clamp(mSpecularProbability, 0.1f, 0.9f);
        break;
    }
    }
}

LobeValue ScatterLobe::evaluate(const Vec3f& L) const {
    const float NoL = dot(mS.normal, L);
    if (!mActive || NoL <= 0.0f || dot(L, mS.geometricNormal) <= 0.0f) return {};
    if (mKind == Kind::Cosine) {
        const float c = NoL / kPiF;
        return {{c, c, c}, c};
    }
    const Vec3f& V = mS.toViewer;
    const Vec3f H = normalize(V + L);
    const float NoH = std::clamp(dot(mS.normal, H), 0.0f, 1.0f);
    // Visible-normal pdf of the reflected direction: D·G1(V)/(4·NoV).
    const float specPdf = ggxD(mA2, NoH) * smithG1(mA2, mNoV) / (4.0f * mNoV);
    if (mKind == Kind::Specular) {
        const Vec3f f = schlickF(mS.brdf.specularColor, dot(V, H)) *
                        (ggxD(mA2, NoH) * smithJointApproxVis(mA2, mNoV, NoL));
        return {f * NoL, specPdf};
    }
    const float pdf = (1.0f - mSpecularProbability) * NoL / kPiF + mSpecularProbability * specPdf;
    return {mS.brdf.evaluate(mS.normal, V, L) * NoL, pdf};
}

bool ScatterLobe::sample(float choose, float u, float v, Vec3f& L) const {
    if (!mActive) return false;
    const bool specular = mKind == Kind::Specular ||
                          (mKind == Kind::Bsdf && choose < mSpecularProbability);
    if (specular)
        L = normalize(reflect(mS.toViewer, sampleGgxVisibleNormal(mS.normal, mS.toViewer, mAlpha, u, v)));
    else
        L = cosineHemisphere(mS.normal, u, v);
    return dot(mS.normal, L) > 0.0f && dot(L, mS.geometricNormal) > 0.0f;
}

}  // namespace fp
