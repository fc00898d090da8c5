#pragma once
// The preintegrated-skin lookup table that Unreal reads from the engine texture
// View.PreIntegratedBRDF (an asset, algorithms §9.6 and §13 gap 3). framepass computes its own from
// Penner's preintegrated skin diffusion (Penner & Borshukov, GPU Pro 2 / SIGGRAPH 2011): a sphere
// of radius r lit at angle θ, its irradiance blurred around the great circle by the skin diffusion
// profile R:
//   D(θ, r) = ∫ saturate(cos(θ + x)) R(2r·sin(x/2)) dx / ∫ R(2r·sin(x/2)) dx,   x ∈ [−π, π].
// The table holds max(D − saturate(cosθ), 0) per RGB: Unreal adds the table to its default-lit
// Lambert term as "transmission", so only the light diffusion brings beyond Lambert belongs in it
// (mostly the red glow past the terminator).
//
// Axes (texel centres on the corners, i/(kSize − 1), so u = 0.5 and v = 0 are exact texels):
//   u = saturate(NoL·0.5 + 0.5), i.e. cosθ = 2u − 1;
//   v = 1 − Opacity, mapped to curvature 1/r = v / kMinRadiusMm: v = 0 is a flat surface (no
//   scattering, LUT 0), v = 1 the strongest scattering, a 2 mm sphere. Linear in curvature because
//   D − Lambert grows linearly with curvature for gently curved skin, so equal steps in v give
//   roughly equal steps in the result.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <vector>

namespace fp {

/// The table as per-pixel code reads it, on the host or (copied) on the GPU.
struct PreintegratedSkinView {
    static constexpr int kSize = 65;  //!< texels per axis (64 intervals)
    const Vec3f* texels = nullptr;    //!< row-major, v rows of u texels

    /// Bilinear lookup, (u, v) clamped to [0, 1]; NaN reads as 0.
    FP_HD Vec3f sample(float u, float v) const {
        // Written so that NaN fails both comparisons and reads texel 0.
        const float cu = u > 0.0f ? (u < 1.0f ? u : 1.0f) : 0.0f;
        const float cv = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
        const float x = cu * (kSize - 1), y = cv * (kSize - 1);
        const int i = int(x) < kSize - 2 ? int(x) : kSize - 2, j = int(y) < kSize - 2 ? int(y) : kSize - 2;
        const float fx = x - float(i), fy = y - float(j);
        const Vec3f* row0 = texels + j * kSize + i;
        const Vec3f* row1 = row0 + kSize;
        const Vec3f bottom = row0[0] * (1.0f - fx) + row0[1] * fx;
        const Vec3f top = row1[0] * (1.0f - fx) + row1[1] * fx;
        return bottom * (1.0f - fy) + top * fy;
    }
};

class PreintegratedSkinLut {
public:
    static constexpr int kSize = PreintegratedSkinView::kSize;  //!< texels per axis (64 intervals)
    static constexpr float kMinRadiusMm = 2.0f;  //!< sphere radius at v = 1 [mm]

    /// The table, built on first use (thread-safe).
    static const PreintegratedSkinLut& instance();

    /// PreintegratedSkinView::sample of the table.
    Vec3f sample(float u, float v) const { return view().sample(u, v); }
    PreintegratedSkinView view() const { return {mTexels.data()}; }
    const std::vector<Vec3f>& texels() const { return mTexels; }

private:
    PreintegratedSkinLut();

    std::vector<Vec3f> mTexels;  // row-major, v rows of u texels
};

}  // namespace fp
