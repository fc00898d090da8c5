#pragma once
// Unreal's environment BRDF (algorithms §8.4): the split-sum scale A and bias B that turn the
// prefiltered radiance of a reflection into reflected radiance, EnvBRDF = F0·A + saturate(50·F0.g)·B.
// framepass builds its own preintegrated table the way Unreal's SystemTextures generates
// PreIntegratedGF (128 NoV × 32 roughness texels, 128 Hammersley samples of the GGX lobe per texel,
// 16-bit unorm), like the preintegrated-skin table, and keeps the analytic fit Unreal uses on
// mobile beside it for comparison.
#include "foundation/Math.h"

#include <vector>

namespace fp {

/// The split-sum terms: reflected radiance = prefiltered radiance × (F0·a + saturate(50·F0.g)·b).
struct EnvBRDFTerms {
    float a = 0, b = 0;
};

/// F0·A + saturate(50·F0.g)·B: below 2 % F0 counts as pre-baked shadowing, as in Unreal's Fresnel.
inline Vec3f applyEnvBRDF(const Vec3f& F0, EnvBRDFTerms t) {
    const float cut = saturate(50.0f * F0.y) * t.b;
    return F0 * t.a + Vec3f{cut, cut, cut};
}

/// ∫ of the GGX specular lobe (Smith joint approximate visibility) over the hemisphere with
/// F = 1 − Fc (→ a) and F = Fc (→ b), Fc = (1 − VoH)⁵, estimated with `samples` Hammersley points
/// exactly as Unreal's generator does (E1 = i/samples, E2 = radical inverse of i).
EnvBRDFTerms integrateEnvBRDF(float NoV, float roughness, int samples);

/// Unreal's EnvBRDFApprox (Lazarov-style analytic fit, algorithms §8.4).
EnvBRDFTerms envBRDFApprox(float NoV, float roughness);

class EnvBRDFLut {
public:
    static constexpr int kNoVTexels = 128, kRoughnessTexels = 32, kSamples = 128;

    /// The table, built on first use (thread-safe).
    static const EnvBRDFLut& instance();

    /// Bilinear lookup on texel centres, clamped at the edges (Unreal's bilinear-clamp sampler).
    EnvBRDFTerms lookup(float NoV, float roughness) const;

    /// The stored texel (i, j): NoV = (i + 0.5)/128, roughness = (j + 0.5)/32.
    EnvBRDFTerms texel(int i, int j) const { return mTexels[size_t(j) * kNoVTexels + size_t(i)]; }

private:
    EnvBRDFLut();
    std::vector<EnvBRDFTerms> mTexels;  // row-major, roughness rows of NoV texels
};

}  // namespace fp
