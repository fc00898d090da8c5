#pragma once
// Hierarchical Z (algorithms §2): mip chains of device Z holding, per texel, the furthest (min,
// reversed Z) and closest (max) depth of the pixels beneath it. SSR and SSGI march against the
// furthest chain; the reduced previous colour uses it as its reference depth.
#include "framework/Params.h"
#include "framework/Pass.h"

namespace fp {

struct HZBParams {
    bool halfPrecision = true;  //!< round texels to half as Unreal's PF_R16F target does
};

class HZBPass final : public PassWithParams<HZBParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;

    /// Unreal 4.27 sizing: mip 0 is 2^(⌈log2 W⌉−1) × 2^(⌈log2 H⌉−1) and there are as many mips
    /// as the larger exponent (1920×1080 → 1024×1024, 10 mips).
    static std::vector<Extent> mipExtents(Extent frame);

    FP_PASS_HAS_CUDA_KERNEL  // HZBPass.cu
};

}  // namespace fp
