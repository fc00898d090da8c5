#pragma once
// Unreal's screen-space denoiser in its DiffuseAndAmbientOcclusion configuration, the one it runs
// after ray-traced GI (algorithms §12.5): a 16-tap reconstruction and a pre-convolution sized by
// the GI rays' hit distance, temporal accumulation towards 4096 samples, a history convolution.
// It denoises the irradiance and the AO together, as Unreal's does.
#include "framework/Params.h"
#include "framework/Pass.h"
#include "screenspace/SignalDenoiser.h"

namespace fp {

struct GIDenoiseParams {
    int denoiser = 1;                   //!< 0 off (raw trace), 1/2 on
    int reconstructionSamples = 16;     //!< taps of the reconstruction, 1–56
    int preConvolution = 1;             //!< pre-convolution passes
    bool temporalAccumulation = true;   //!< accumulate across frames
    int historyConvolutionSamples = 1;  //!< taps of the post filter
    float historyConvolutionSpread = 3; //!< the post filter's radius, pixels
};

class GIDenoisePass final : public PassWithParams<GIDenoiseParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    /// What the denoiser runs on either backend.
    ssd::Denoising denoising() const;
    PassMemory memoryBytes(Extent frame) const override {
        return ssd::memoryOf(frame, 4, mParams.denoiser > 0, mParams.temporalAccumulation);
    }

    FP_PASS_HAS_CUDA_KERNEL  // GIDenoisePass.cu
};

}  // namespace fp
