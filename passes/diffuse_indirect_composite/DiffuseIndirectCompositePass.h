#pragma once
// DiffuseIndirectComposite (algorithms §7): applies the denoised SSGI and its AO to scene colour,
// SceneColor × FinalAO + diffuse albedo × SSGI. Unreal 4.27 multiplies DiffuseColor and point-
// upsamples a half-resolution trace; UE5 adds per-shading-model terms (subsurface, skin, foliage,
// cloth, hair) and a depth-tested 2×2 bilinear upsample.
#include "framework/Params.h"
#include "framework/Pass.h"

#include <string>

namespace fp {

struct DiffuseIndirectCompositeParams {
    std::string engine = "ue4.27";        //!< "ue4.27" (simple term) or "ue5" (per shading model)
    float aoStaticFraction = 1.0f;        //!< PP AmbientOcclusionStaticFraction
};

class DiffuseIndirectCompositePass final : public PassWithParams<DiffuseIndirectCompositeParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

    /// UE5's half-resolution upsample: a 2×2 bilinear tap is dropped when its surface is farther
    /// than 16 × 2√2 pixel radii from the pixel's (algorithms §7.3).
    static constexpr double kUpsampleRejection = 16.0 * 2.0 * 1.4142135623730951;

    FP_PASS_HAS_CUDA_KERNEL  // DiffuseIndirectCompositePass.cu

private:
    bool ue5() const { return mParams.engine == "ue5"; }
};

}  // namespace fp
