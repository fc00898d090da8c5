#pragma once
// Unreal's screen-space denoiser in its AmbientOcclusion configuration, the one it runs after
// ray-traced AO (algorithms §12.5): a 16-tap reconstruction and two pre-convolutions sized by the
// AO rays' closest hit, temporal accumulation, a 7-pixel history convolution.
#include "framework/Params.h"
#include "framework/Pass.h"
#include "screenspace/SignalDenoiser.h"

namespace fp {

struct AODenoiseParams {
    int denoiser = 2;                   //!< 0 off (raw mask), 1/2 on
    int reconstructionSamples = 16;     //!< taps of the reconstruction, 1–56
    int preConvolution = 2;             //!< pre-convolution passes
    bool temporalAccumulation = true;   //!< accumulate across frames
    int historyConvolutionSamples = 1;  //!< taps of the post filter
    float historyConvolutionSpread = 7; //!< the post filter's radius, pixels
};

class AODenoisePass final : public PassWithParams<AODenoiseParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    /// What the denoiser runs on either backend.
    ssd::Denoising denoising() const;
    PassMemory memoryBytes(Extent frame) const override {
        return ssd::memoryOf(frame, 1, mParams.denoiser > 0, mParams.temporalAccumulation);
    }

    FP_PASS_HAS_CUDA_KERNEL  // AODenoisePass.cu
};

}  // namespace fp
