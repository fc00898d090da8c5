#pragma once
// Ray-traced shadows of one light (algorithms §9, Unreal's RayTracingOcclusionRGS): per pixel,
// shadow rays from the position reconstructed from depth, biased towards the camera and along the
// normal. On the CPU through Embree in packets of neighbouring pixels (rtcOccluded16 where the
// CPU has AVX-512, else rtcOccluded8), the per-pixel work in SIMD lanes (ShadowLanes.h); on the
// GPU one pixel per thread through framepass's own BVH (RTShadowsKernel.h, foundation/Bvh.h). Subsurface and
// hair pixels whose ray is blocked trace the inverted ray through their own object: the thickness
// gives a transmission exp(−density·thickness). Outputs visibility, transmission, the closest
// occluder distance (for the denoiser) and the light-attenuation encoding (algorithms §9.5).
#include "framework/Params.h"
#include "framework/Pass.h"

#include <string>

namespace fp {

struct RTShadowsParams {
    std::string light;           //!< the light's name ("" = the scene's only light)
    int samplesPerPixel = -1;    //!< −1 = the light's own
    float normalBias = 0.1f;     //!< cm (min 0.01)
    bool transmission = true;    //!< the light's bTransmission: subsurface/hair thickness rays
    float lodTransitionStart = 4000.0f;  //!< cm
    float lodTransitionEnd = 5000.0f;    //!< cm
    bool rayPackets = true;      //!< Embree packets (8 or 16); false traces one ray at a time
    bool lanes = true;           //!< set-up and rays in SIMD lanes; false: the scalar reference
    /// "embree": Embree's packets on the CPU; "bvh": framepass's own BVH, one pixel at a time,
    /// the GPU's code (the GPU always traverses it).
    std::string traversal = "embree";
};

class RTShadowsPass final : public PassWithParams<RTShadowsParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    FP_PASS_HAS_CUDA_KERNEL  // RTShadowsPass.cu

};

}  // namespace fp
