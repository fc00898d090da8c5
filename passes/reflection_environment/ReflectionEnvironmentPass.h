#pragma once
// ReflectionEnvironment + SkyLighting (algorithms §8): after the lights, adds the sky light's
// diffuse (order-3 SH of the sky, dimmed by the screen-space and material AO) and the specular
// reflections: the screen-space reflections first, then, in the weight they leave and under
// Lagarde's specular occlusion, the reflection captures around the pixel (parallax-corrected,
// composited under each other in ascending radius) and the sky, each prefiltered at the
// roughness's mip, all × the preintegrated EnvBRDF; clear coat as two layers. Unlit pixels and
// the sky are untouched; hair gets no reflections.
#include "framework/Params.h"
#include "framework/Pass.h"
#include "shading/Cubemap.h"
#include "shading/ReflectionCaptures.h"
#include "passes/reflection_environment/ReflectionEnvironmentKernel.h"

#include <memory>

namespace fp {

struct Environment;
struct SkyLight;

struct ReflectionEnvironmentParams {
    bool reflections = true;      //!< r.ReflectionEnvironment: the specular half
    bool skyDiffuse = true;       //!< the sky light's diffuse
    bool specularOcclusion = true;  //!< Lagarde's AO on the reflection weight (§8.2 step 5)
};

class ReflectionEnvironmentPass final : public PassWithParams<ReflectionEnvironmentParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

    FP_PASS_HAS_CUDA_KERNEL  // ReflectionEnvironmentPass.cu

    /// reflection_environment::specularOcclusion (the kernel's): Lagarde's, §8.2 step 5.
    static float specularOcclusion(float NoV, float ao, float roughness);

private:
    /// What lights the reflections this frame, from the caches below.
    reflection_environment::Lighting lighting(PassContext& ctx);
    /// The sky resampled to a prefiltered cube and its SH, made on first use and kept while the
    /// sky light is the same one (it does not change from frame to frame).
    struct SkyLighting {
        const SkyLight* source = nullptr;
        Cubemap cube;
        SH3 sh;
    };
    const SkyLighting& skyLighting(const SkyLight& sky);
    /// The captures' prefiltered cubemaps, made on first use and kept while the environment is
    /// the same one.
    const std::vector<Cubemap>& captureCubes(const Environment& env);

    std::shared_ptr<SkyLighting> mSky;
    const Environment* mCubesOf = nullptr;
    std::vector<Cubemap> mCaptureCubes;
};

}  // namespace fp
