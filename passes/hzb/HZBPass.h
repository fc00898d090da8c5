#pragma once
// Hierarchical Z (algorithms §2): mip chains of device Z holding, per texel, the furthest (min,
// reversed Z) and closest (max) depth of the pixels beneath it. SSR and SSGI march against the
// furthest chain; the reduced previous colour uses it as its reference depth.
#include "passes/core/Params.h"
#include "passes/core/Pass.h"

namespace fp {

struct HZBParams {
    bool halfPrecision = true;  //!< round texels to half as Unreal's PF_R16F target does
};

class HZBPass final : public Pass {
public:
    using Params = HZBParams;
    static ParamSpec<Params> paramSpec();
    explicit HZBPass(const Params& params) : mParams(params) {}

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;

    /// Unreal 4.27 sizing: mip 0 is 2^(⌈log2 W⌉−1) × 2^(⌈log2 H⌉−1) and there are as many mips
    /// as the larger exponent (1920×1080 → 1024×1024, 10 mips).
    static std::vector<Extent> mipExtents(Extent frame);

#if FP_HAVE_CUDA
    bool hasCudaKernel() const override { return true; }
    void executeCuda(PassContext& ctx) override;  // HZBPass.cu
#endif

private:
    Params mParams;
};

}  // namespace fp
