#pragma once
// The previous-frame colour mip chain that SSGI samples at its hits (algorithms §3,
// "SSRTPrevFrameReduction"): last frame's colour reprojected into this frame's pixel grid, with
// leak-free weighting that drops colour whose previous surface is not this pixel's surface.
#include "framework/Params.h"
#include "framework/Pass.h"

namespace fp {

struct PrevColorReductionParams {
    bool leakFree = true;  //!< previous colour + depth (1) or TAA history (0)
    float preExposureCorrection = 1.0f;  //!< PreExposure_current / PreExposure_previous, (0, 1e6]
    bool removeSky = false;  //!< UE5 only: colour beyond skyDistance is zeroed (4.27 keeps it)
    float skyDistance = 1e7f;  //!< sky distance in scene units (UE5)
};

class PrevColorReductionPass final : public PassWithParams<PrevColorReductionParams> {
public:
    static constexpr int kMipCount = 5;
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    PassMemory memoryBytes(Extent frame) const override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;

    /// Mip 0 is half resolution rounded up to a multiple of 16; five mips (algorithms §3.1).
    static std::vector<Extent> mipExtents(Extent frame);
    FP_PASS_HAS_CUDA_KERNEL  // PrevColorReductionPass.cu
};

}  // namespace fp
