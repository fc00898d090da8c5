#pragma once
// Unreal's screen-space denoiser in its SSGI configuration (algorithms §6.2): an 8-tap bilateral
// reconstruction (plane distance × normal⁴) at the trace resolution, then temporal accumulation
// with the frames before — reprojection through the history's camera (or velocity), a stochastic
// 2×2 history tap validated bilaterally, a 1.25σ neighbourhood clamp, AO-driven rejection and a
// sample-count-weighted running mean whose history is capped at 64 samples.
#include "framework/Params.h"
#include "framework/Pass.h"

namespace fp {

struct SSGIDenoiseParams {
    int denoiser = 1;                 //!< 0 off (raw trace), 1/2 on
    bool temporalAccumulation = true; //!< accumulate across frames
    bool halfRes = false;             //!< the trace ran at half resolution
};

class SSGIDenoisePass final : public PassWithParams<SSGIDenoiseParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    PassMemory memoryBytes(Extent frame) const override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;

    FP_PASS_HAS_CUDA_KERNEL  // SSGIDenoisePass.cu
};

}  // namespace fp
