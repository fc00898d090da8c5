#pragma once
// Ray-traced ambient occlusion (algorithms §12.1, Unreal 4.27's RTAO): per pixel, cosine-weighted
// rays about the normal the depth buffer gives, up to the AO radius; any hit within it occludes
// the ray. Traced through Embree in full packets of the tile's rays (each row's set-up and rays in
// SIMD lanes, AmbientOcclusionLanes.h), or through framepass's own BVH
// one pixel at a time (traversal "bvh": the GPU's code, which the GPU runs). Outputs the AO (Unreal's
// mask, fed to the composite where SSGI's AO goes) and the closest hit (its denoiser's input).
#include "framework/Params.h"
#include "framework/Pass.h"

#include <string>

namespace fp {

struct RTAmbientOcclusionParams {
    int samplesPerPixel = -1;  //!< −1: the post-process volume's RayTracingAOSamplesPerPixel, 1
    float intensity = 1.0f;    //!< RayTracingAOIntensity: a blocked ray counts 1 − intensity
    float radius = 200.0f;     //!< RayTracingAORadius, cm: the rays' length
    float normalBias = 0.1f;   //!< cm (min 0.01), as rt_shadows
    std::string traversal = "embree";  //!< "embree" (packets) or "bvh" (the GPU's code)
    bool lanes = true;         //!< Embree's path: set-up and rays in SIMD lanes; false: the scalar reference
};

namespace rtao {
struct FrameSetup;
}

class RTAmbientOcclusionPass final : public PassWithParams<RTAmbientOcclusionParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

    FP_PASS_HAS_CUDA_KERNEL  // RTAmbientOcclusionPass.cu

private:
    /// What every pixel of the frame shares (either backend).
    rtao::FrameSetup frameSetup(PassContext& ctx) const;
};

}  // namespace fp
