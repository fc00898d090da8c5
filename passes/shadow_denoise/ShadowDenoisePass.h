#pragma once
// The shadow configuration of Unreal's screen-space denoiser (algorithms §6.3), spatial part: the
// penumbra of a light is as wide as the light looks from the occluder, so each pixel's blur radius
// comes from its closest occluder distance and the light's size (directional: tan(½·angle) × the
// distance; local: radius × d/(D − d)). Golden-angle taps inside that radius are weighted by the
// receiver's plane and normal, so contact shadows stay sharp and shadows do not bleed across
// creases. Writes the light-attenuation encoding (algorithms §9.5) of the filtered result.
#include "framework/Params.h"
#include "framework/Pass.h"

#include <string>

namespace fp {

struct ShadowDenoiseParams {
    int denoiser = 2;               //!< 0 passes the raw shadow through
    std::string light;              //!< the light's name ("" = the scene's only light)
    int reconstructionSamples = 8;  //!< taps per filtering pass
    int preConvolution = 1;         //!< extra passes before the reconstruction
    float maxRadius = 32.0f;        //!< largest blur radius, pixels
};

class ShadowDenoisePass final : public PassWithParams<ShadowDenoiseParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    PassMemory memoryBytes(Extent frame) const override;

    FP_PASS_HAS_CUDA_KERNEL  // ShadowDenoisePass.cu
};

}  // namespace fp
