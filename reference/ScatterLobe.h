#pragma once
// The directional weights the reference tracer integrates incoming radiance against, each with
// its importance sampler and pdf so light sampling and lobe sampling can be combined by multiple
// importance sampling:
//   Cosine    g = cosθ/π             (the cosine-weighted mean of Truth.DiffuseIndirect, §4.8)
//   Specular  g = F·D·Vis·cosθ       (Unreal's GGX lobe alone: Truth.Specular), VNDF sampled
//   Bsdf      g = (diffuse/π + F·D·Vis)·cosθ   (the whole surface, for path vertices)
#include "foundation/HostDevice.h"
#include "foundation/Random.h"
#include "foundation/Sampling.h"
#include "shading/DirectLighting.h"

namespace fp {

struct LobeValue {
    Vec3f weight;  //!< g(ω)
    float pdf = 0; //!< solid-angle pdf of the lobe's own sampler at ω
};

/// A lobe at a surface point; every member runs on the CPU and in CUDA kernels (the
/// screen-space oracle), the same arithmetic on both.
class ScatterLobe {
public:
    enum class Kind { Cosine, Specular, Bsdf };

    FP_HD ScatterLobe(Kind kind, const SurfacePoint& s) : mKind(kind), mS(s) {
        mNoV = dot(s.normal, s.toViewer);
        // The α BRDF.h evaluates with (roughness clamped for light sources), so f/pdf stays
        // consistent down to roughness 0.
        const float r = s.brdf.roughness < kMinLightRoughness ? kMinLightRoughness : s.brdf.roughness;
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
                if (d > 0.0f && sp > 0.0f)
                    mSpecularProbability = mSpecularProbability < 0.1f   ? 0.1f
                                           : mSpecularProbability > 0.9f ? 0.9f
                                                                         : mSpecularProbability;
                break;
            }
        }
    }

    /// False when the lobe is empty (nothing to integrate: skip it).
    FP_HD bool active() const { return mActive; }

    FP_HD LobeValue evaluate(const Vec3f& L) const {
        const float NoL = dot(mS.normal, L);
        if (!mActive || NoL <= 0.0f || dot(L, mS.geometricNormal) <= 0.0f) return {};
        if (mKind == Kind::Cosine) {
            const float c = NoL / kPiF;
            return {{c, c, c}, c};
        }
        const Vec3f& V = mS.toViewer;
        const Vec3f H = normalize(V + L);
        const float NoH = saturate(dot(mS.normal, H));
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

    /// Draws a direction from three uniforms; false if it leaves below the surface.
    FP_HD bool sample(float choose, float u, float v, Vec3f& L) const {
        if (!mActive) return false;
        const bool specular = mKind == Kind::Specular || (mKind == Kind::Bsdf && choose < mSpecularProbability);
        if (specular)
            L = normalize(reflect(mS.toViewer, sampleGgxVisibleNormal(mS.normal, mS.toViewer, mAlpha, u, v)));
        else
            L = cosineHemisphere(mS.normal, u, v);
        return dot(mS.normal, L) > 0.0f && dot(L, mS.geometricNormal) > 0.0f;
    }

private:
    Kind mKind;
    const SurfacePoint& mS;
    bool mActive = true;
    float mNoV = 0, mAlpha = 0, mA2 = 0;
    float mSpecularProbability = 0;  //!< Bsdf: chance of drawing from the GGX lobe
};

}  // namespace fp
