#pragma once
// Ray-traced reflections, Unreal 4.27's (algorithms §12.4, RayTracingReflections.usf): per pixel
// a mirror or GGX (visible-normal) ray, its closest hit shaded with the scene's material and
// lights (one shadow ray a light), its emission and the sky light's diffuse; a miss takes the sky.
// The output is what SSR's is — pre-BRDF radiance with coverage in alpha — so
// reflection_environment takes it in SSR's place and applies EnvBRDF. CPU, through Embree.
#include "framework/Params.h"
#include "framework/Pass.h"
#include "shading/ReflectionHits.h"

#include <memory>

namespace fp {


struct RTReflectionsParams {
    int samplesPerPixel = -1;   //!< −1: the post-process volume's 1
    float maxRoughness = -1.0f; //!< −1: the post-process volume's 0.6
    int shadows = -1;           //!< −1: hard (1); 0 off; 1, 2 shadow rays
    float normalBias = 0.1f;    //!< cm: the reflection ray's origin bias
    /// r.RayTracing.Reflections.Hybrid: a hit that lands on screen within 5 cm of the depth
    /// buffer takes this frame's lit colour there instead of being shaded.
    bool hybrid = false;
    float screenPercentage = 100.0f;  //!< 25–100: trace one pixel of each block (the denoiser upscales)
    /// A hit's diffuse indirect light: 0, Unreal's, the sky light's SH; n > 0 traced by one
    /// cosine path of n bounces (framepass's; ReflectionHitLighting::indirectBounces).
    int hitIndirectBounces = 0;
};

class RTReflectionsPass final : public PassWithParams<RTReflectionsParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;

private:
    std::shared_ptr<const ReflectedSky> mSky;  // made once per sky light
};

}  // namespace fp
