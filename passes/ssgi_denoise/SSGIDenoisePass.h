#pragma once
// Unreal's screen-space denoiser in its SSGI configuration (reference §6.2): an 8-tap bilateral
// reconstruction (plane distance × normal⁴) at the trace resolution, then temporal accumulation
// with the frames before — reprojection through the history's camera (or velocity), a stochastic
// 2×2 history tap validated bilaterally, a 1.25σ neighbourhood clamp, AO-driven rejection and a
// sample-count-weighted running mean whose history is capped at 64 samples.
#include "passes/core/Params.h"
#include "passes/core/Pass.h"

#include <array>

namespace fp {

struct SSGIDenoiseParams {
    int denoiser = 1;                 //!< 0 off (raw trace), 1/2 on
    bool temporalAccumulation = true; //!< accumulate across frames
    bool halfRes = false;             //!< the trace ran at half resolution
};

class SSGIDenoisePass final : public Pass {
public:
    using Params = SSGIDenoiseParams;
    static ParamSpec<Params> paramSpec();
    explicit SSGIDenoisePass(const Params& params) : mParams(params) {}

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;

    static constexpr int kTracks = 4;       //!< one per pixel of a 2×2 quad
    static constexpr int kTaps = 8;         //!< reconstruction samples besides the centre
    static constexpr float kClampSigma = 1.25f;
    static constexpr float kTargetSamples = 128.0f;
    static constexpr float kHistoryCap = 64.0f;  //!< R8 storage of SampleCount/64
    struct Offset {
        float x, y;  //!< from the quad centre, pixels (half-integers)
    };
    /// The reconstruction kernel: per track, 8 pixel offsets from the centre of the 2×2 quad.
    static const std::array<std::array<Offset, kTaps>, kTracks>& kernel();

private:
    Params mParams;
};

}  // namespace fp
