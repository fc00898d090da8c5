#pragma once
// Ray-traced reflections, Unreal 4.27's (algorithms §12.4, RayTracingReflections.usf): per pixel
// a mirror or GGX (visible-normal) ray, its closest hit shaded with the scene's material and
// lights (one shadow ray a light), its emission and the sky light's diffuse; a miss takes the sky.
// The output is what SSR's is — pre-BRDF radiance with coverage in alpha — so
// reflection_environment takes it in SSR's place and applies EnvBRDF. Traced through Embree, or
// through framepass's own BVH (traversal "bvh": the GPU's code, which the GPU runs).
#include "framework/Params.h"
#include "framework/Pass.h"
#include "shading/ReflectionHits.h"

#include <memory>
#include <string>

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
    std::string traversal = "embree";  //!< "embree" or "bvh" (the GPU's code)
    bool waves = true;  //!< Embree: a tile row's rays a step at a time, in packets
};

namespace rtr {
struct FrameSetup;
struct Frame;
}  // namespace rtr
class DirectLighting;

class RTReflectionsPass final : public PassWithParams<RTReflectionsParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;

#if FP_HAVE_CUDA
    /// The GPU's paths read no sky: a hit's traced indirect light keeps the pass on the CPU (under
    /// a sky light it would see it).
    bool hasCudaKernel() const override { return mParams.hitIndirectBounces == 0; }
    void executeCuda(PassContext& ctx) override;  // RTReflectionsPass.cu
#endif

private:
    /// What every texel of the frame shares (either backend); makes the sky's cubemap first.
    rtr::FrameSetup frameSetup(PassContext& ctx);
    /// The texels of `f` through Embree a tile row at a time, each step's rays in packets
    /// (reflectionTexel's steps, the same bits).
    void traceWaves(PassContext& ctx, const rtr::FrameSetup& setup, const rtr::Frame& f,
                    Extent trace, const DirectLighting& lighting);
    std::shared_ptr<const ReflectedSky> mSky;  // made once per sky light
};

}  // namespace fp
