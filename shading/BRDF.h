#pragma once
// Unreal's default-lit BRDF terms (algorithms §7/§9 and Unreal's BRDF.ush as described there):
// Lambert diffuse, GGX distribution, Smith joint visibility approximation, Schlick Fresnel with
// Unreal's 2% cut-off. Shared by the capture renderer and the lighting passes.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <algorithm>
#include <cmath>

namespace fp {

/// Roughness is clamped away from 0 for analytic lights: a perfect mirror lit by a point has a
/// Dirac lobe, which a finite BRDF value cannot represent (and would turn into NaN).
constexpr float kMinLightRoughness = 0.02f;

// The terms below are templates on their number type T: float, or a SIMD vector of pixels
// (foundation/LaneFloat.h), the same operations either way.

/// Unreal's Pow4 and Pow5 (Common.ush): products, not pow().
template <class T>
FP_HD T pow4(T x) {
    const T x2 = x * x;
    return x2 * x2;
}

template <class T>
FP_HD T pow5(T x) {
    return pow4(x) * x;
}

template <class T>
FP_HD T ggxD(T a2, T NoH) {
    const T d = (NoH * a2 - NoH) * NoH + 1.0f;
    return a2 / (kPiF * d * d);
}

/// Vis = G/(4·NoL·NoV), Heitz's joint Smith approximation as Unreal writes it.
template <class T>
FP_HD T smithJointApproxVis(T a2, T NoV, T NoL) {
    const T a = sqrtOf(a2);
    const T visV = NoL * (NoV * (1.0f - a) + a);
    const T visL = NoV * (NoL * (1.0f - a) + a);
    return 0.5f / maxLike(visV + visL, T(1e-8f));
}

/// Schlick with Unreal's rule that F0 below 2% means "no specular at all" (saturate(50·F0.g)).
/// Fc = Pow5(1 − VoH) as Unreal's F_Schlick writes it (inferred from memory of BRDF.ush): three
/// multiplies, which SIMD lanes repeat exactly where std::pow has no exact vector twin.
template <class T>
FP_HD Vec3T<T> schlickF(const Vec3T<T>& F0, T VoH) {
    const T fc = pow5(T(1.0f) - saturate(VoH));
    const T cut = saturate(50.0f * F0.y);
    const T cutFc = cut * fc;
    return Vec3T<T>{cutFc, cutFc, cutFc} + F0 * (1.0f - fc);
}

/// The default-lit BRDF f(V, L) of a surface of diffuse colour `diffuse`, F0 `specular` and
/// `roughness`, for unit N, V, L with N·L > 0 (SurfaceBRDF::evaluate); T: float or float lanes.
template <class T>
FP_HD Vec3T<T> brdfOf(const Vec3T<T>& diffuse, const Vec3T<T>& specular, T roughness,
                      const Vec3T<T>& N, const Vec3T<T>& V, const Vec3T<T>& L) {
    const T NoL = dot(N, L), NoV = maxLike(dot(N, V), T(1e-4f));
    const Vec3T<T> H = normalize(V + L);
    const T NoH = saturateOf(dot(N, H));  // std::clamp(·, 0, 1)
    const T VoH = dot(V, H);
    const T r = ifThenElse(roughness < kMinLightRoughness, T(kMinLightRoughness), roughness);
    const T a2 = r * r * r * r;  // α = roughness², a2 = α²
    const Vec3T<T> spec = schlickF(specular, VoH) * (ggxD(a2, NoH) * smithJointApproxVis(a2, NoV, NoL));
    return diffuse * (1.0f / kPiF) + spec;
}

struct SurfaceBRDF {
    Vec3f diffuseColor;   //!< BaseColor·(1 − Metallic)
    Vec3f specularColor;  //!< F0 = lerp(0.08·Specular, BaseColor, Metallic)
    float roughness;

    FP_HD static SurfaceBRDF fromMaterial(const Vec3f& baseColor, float metallic, float specular,
                                    float roughness) {
        const float dielectric = 0.08f * specular;
        const Vec3f f0 = Vec3f{dielectric, dielectric, dielectric} * (1.0f - metallic) +
                         baseColor * metallic;
        return {baseColor * (1.0f - metallic), f0, roughness};
    }

    /// f(V, L) for unit N, V, L on the same side (NoL, NoV > 0), per steradian.
    FP_HD Vec3f evaluate(const Vec3f& N, const Vec3f& V, const Vec3f& L) const {
        const float NoL = dot(N, L);
        if (NoL <= 0.0f) return {};
        return brdfOf<float>(diffuseColor, specularColor, roughness, N, V, L);
    }
};

}  // namespace fp
