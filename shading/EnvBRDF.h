#pragma once
// Unreal's environment BRDF (algorithms §8.4): the split-sum scale A and bias B that turn the
// prefiltered radiance of a reflection into reflected radiance, EnvBRDF = F0·A + saturate(50·F0.g)·B.
// framepass builds its own preintegrated table the way Unreal's SystemTextures generates
// PreIntegratedGF (128 NoV × 32 roughness texels, 128 Hammersley samples of the GGX lobe per texel,
// 16-bit unorm), like the preintegrated-skin table, and keeps the analytic fit Unreal uses on
// mobile beside it for comparison.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <vector>

namespace fp {

/// The split-sum terms: reflected radiance = prefiltered radiance × (F0·a + saturate(50·F0.g)·b).
struct EnvBRDFTerms {
    float a = 0, b = 0;
};

/// F0·A + saturate(50·F0.g)·B: below 2 % F0 counts as pre-baked shadowing, as in Unreal's Fresnel.
FP_HD inline Vec3f applyEnvBRDF(const Vec3f& F0, EnvBRDFTerms t) {
    const float cut = saturate(50.0f * F0.y) * t.b;
    return F0 * t.a + Vec3f{cut, cut, cut};
}

/// ∫ of the GGX specular lobe (Smith joint approximate visibility) over the hemisphere with
/// F = 1 − Fc (→ a) and F = Fc (→ b), Fc = (1 − VoH)⁵, estimated with `samples` Hammersley points
/// exactly as Unreal's generator does (E1 = i/samples, E2 = radical inverse of i).
EnvBRDFTerms integrateEnvBRDF(float NoV, float roughness, int samples);

/// Unreal's EnvBRDFApprox (Lazarov-style analytic fit, algorithms §8.4).
EnvBRDFTerms envBRDFApprox(float NoV, float roughness);

/// The table as per-pixel code reads it, on the host or (copied) on the GPU.
struct EnvBRDFView {
    static constexpr int kNoVTexels = 128, kRoughnessTexels = 32;
    const EnvBRDFTerms* texels = nullptr;  //!< row-major, roughness rows of NoV texels

    /// Bilinear lookup on texel centres, clamped at the edges (Unreal's bilinear-clamp sampler).
    FP_HD EnvBRDFTerms lookup(float NoV, float roughness) const {
        int i, j;
        float fx, fy;
        coordinate(NoV, kNoVTexels, i, fx);
        coordinate(roughness, kRoughnessTexels, j, fy);
        const EnvBRDFTerms t00 = at(i, j), t10 = at(i + 1, j), t01 = at(i, j + 1), t11 = at(i + 1, j + 1);
        const float topA = t00.a * (1 - fx) + t10.a * fx, bottomA = t01.a * (1 - fx) + t11.a * fx;
        const float topB = t00.b * (1 - fx) + t10.b * fx, bottomB = t01.b * (1 - fx) + t11.b * fx;
        return {topA * (1 - fy) + bottomA * fy, topB * (1 - fy) + bottomB * fy};
    }
    FP_HD EnvBRDFTerms at(int i, int j) const { return texels[j * kNoVTexels + i]; }

private:
    // Texel centres sit at (i + 0.5)/size; outside the outer centres the edge texel holds.
    FP_HD static void coordinate(float u, int size, int& i0, float& f) {
        float x = std::isnan(u) ? 0.0f : u * float(size) - 0.5f;
        x = x < 0.0f ? 0.0f : (x > float(size - 1) ? float(size - 1) : x);
        i0 = int(x) < size - 2 ? int(x) : size - 2;
        f = x - float(i0);
    }
};

class EnvBRDFLut {
public:
    static constexpr int kNoVTexels = EnvBRDFView::kNoVTexels;
    static constexpr int kRoughnessTexels = EnvBRDFView::kRoughnessTexels, kSamples = 128;

    /// The table, built on first use (thread-safe).
    static const EnvBRDFLut& instance();

    /// EnvBRDFView::lookup of the table.
    EnvBRDFTerms lookup(float NoV, float roughness) const { return view().lookup(NoV, roughness); }
    EnvBRDFView view() const { return {mTexels.data()}; }
    const std::vector<EnvBRDFTerms>& texels() const { return mTexels; }

    /// The stored texel (i, j): NoV = (i + 0.5)/128, roughness = (j + 0.5)/32.
    EnvBRDFTerms texel(int i, int j) const { return mTexels[size_t(j) * kNoVTexels + size_t(i)]; }

private:
    EnvBRDFLut();
    std::vector<EnvBRDFTerms> mTexels;  // row-major, roughness rows of NoV texels
};

}  // namespace fp
