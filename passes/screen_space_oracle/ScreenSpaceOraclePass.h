#pragma once
// framepass's own screen-space reference, not one of Unreal's passes: the best any screen-space
// method can do with what a capture holds. Per pixel, many rays (the truth tracer's lobes: cosine
// for diffuse, the pixel's GGX lobe for specular) are marched in half-pixel steps against the
// full-resolution depth, each sample compared with the tangent plane of the pixel it lands in
// (so a flat surface is exact at any slope), and a hit reads last frame's colour where the hit
// pixel's surface was, at full resolution: no HZB mips, no reduced colour, no Karis weighting, no
// step schedule. What it misses (off-screen and hidden surfaces) is the screen-space limit; what
// Unreal's passes miss beyond it is their approximation (the error decomposition of `bench`).
#include "framework/Params.h"
#include "framework/Pass.h"

namespace fp {

struct ScreenSpaceOracleParams {
    int rays = 256;           //!< rays per pixel and lobe
    float thickness = 10.0f;  //!< cm: a sample this far behind a pixel's surface still hits it
    float aoRadius = 1.0f;    //!< metres: the radius of aoWithinRadius (capture's Truth.AO radius)
};

class ScreenSpaceOraclePass final : public PassWithParams<ScreenSpaceOracleParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    PassMemory memoryBytes(Extent frame) const override;

    FP_PASS_HAS_CUDA_KERNEL  // ScreenSpaceOraclePass.cu
};

}  // namespace fp
