#pragma once
// Deferred direct lighting of one light (Unreal's RenderLights, algorithms §9.5–9.6): per pixel the
// GBuffer is decoded, the light's unshadowed falloff computed (E for directional lights, I/r² with
// the spot cone for point and spot lights, the area integral for rect lights), the shading model's
// BxDF evaluated (shading/ShadingModelBxDF.h), and surface and transmission terms shadowed
// by the light-attenuation buffer's surface and transmission shadows. The result is added to the
// incoming scene colour, as Unreal's additive light accumulation does (algorithms §7.5).
#include "framework/Params.h"
#include "framework/Pass.h"
#include "passes/deferred_lighting/DeferredLightingKernel.h"
#include "passes/deferred_lighting/DeferredLightingLanes.h"

#include <string>
#include <vector>

namespace fp {

struct DeferredLightingParams {
    std::string light;    //!< the light's name ("" = the scene's only light)
    int rectSamples = 4;  //!< rect lights: an N×N grid of points integrates the area (unshadowed)
    bool lanes = true;    //!< rect lights: default-lit pixels in SIMD lanes (false: scalar reference)
};

class DeferredLightingPass final : public PassWithParams<DeferredLightingParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

    FP_PASS_HAS_CUDA_KERNEL  // DeferredLightingPass.cu

private:
    /// The light as the pixels read it, relative to this frame's eye; a rect light's grid points
    /// go to `rectPoints` (bindFrame points the shape at them, or at their device copy).
    deferred_lighting::LightShape lightShape(PassContext& ctx, std::vector<Vec3f>& rectPoints) const;
};

}  // namespace fp
