#pragma once
// Unreal's screen-space denoiser in its Reflections configuration, the one it runs after
// ray-traced reflections (algorithms §12.5): an 8-tap reconstruction and a pre-convolution whose
// radius follows the reflection lobe's footprint (hit distance × α), temporal accumulation.
#include "framework/Params.h"
#include "framework/Pass.h"
#include "screenspace/SignalDenoiser.h"

namespace fp {

struct ReflectionDenoiseParams {
    int denoiser = 2;                  //!< 0 off (raw reflections), 1/2 on
    int reconstructionSamples = 8;     //!< taps of the reconstruction, 1–56
    int preConvolution = 1;            //!< pre-convolution passes
    bool temporalAccumulation = true;  //!< accumulate across frames
};

class ReflectionDenoisePass final : public PassWithParams<ReflectionDenoiseParams> {
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

    FP_PASS_HAS_CUDA_KERNEL  // ReflectionDenoisePass.cu
};

}  // namespace fp
