#pragma once
// Ray-traced global illumination, Unreal 4.27's brute-force method (algorithms §12.2,
// RayTracingGlobalIlluminationRGS): per pixel, cosine-weighted paths of up to `maxBounces`
// diffuse bounces through the scene; at every hit the lights are sampled with shadow rays (next
// event estimation), and neither the hit's emission nor, unless asked, the sky is added. The
// result is irradiance/π, as SSGI's, for the composite's DiffuseColor × GI. Traced through Embree,
// or through framepass's own BVH (traversal "bvh": the GPU's code, which the GPU runs).
#include "framework/Params.h"
#include "framework/Pass.h"

#include <string>

namespace fp {

struct RTGlobalIlluminationParams {
    int samplesPerPixel = -1;   //!< −1: the post-process volume's 4
    int maxBounces = -1;        //!< −1: the post-process volume's 1
    float maxRayDistance = 1e27f;  //!< cm; a hit beyond it ends the path
    float aoRadius = 200.0f;    //!< cm: a first hit closer than this counts in `ao`
    int nextEventEstimationSamples = 2;  //!< light samples at each hit
    bool evalSkyLight = false;  //!< a bounce ray that misses adds the sky's radiance
    float diffuseThreshold = 0.01f;  //!< pixels whose diffuse colour is darker trace nothing
    float normalBias = 0.1f;    //!< cm (min 0.01), as rt_shadows
    float screenPercentage = 100.0f;  //!< 25–100: trace one pixel of each block (gi_denoise upscales)
    std::string traversal = "embree";  //!< "embree" or "bvh" (the GPU's code)
    bool waves = true;  //!< Embree: a tile row's paths a step at a time, shadow rays in packets
};

namespace rtgi {
struct FrameSetup;
}

class RTGlobalIlluminationPass final : public PassWithParams<RTGlobalIlluminationParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;
    /// Frame pixels per traced texel along each axis: int(100 / screenPercentage), as Unreal's
    /// UpscaleFactor (100 → 1, 50 → 2, 33 → 3, 25 → 4).
    int upscale() const;

#if FP_HAVE_CUDA
    /// The GPU's paths read no sky (BvhTracer): with evalSkyLight the pass stays on the CPU.
    bool hasCudaKernel() const override { return !mParams.evalSkyLight; }
    void executeCuda(PassContext& ctx) override;  // RTGlobalIlluminationPass.cu
#endif

private:
    /// What every texel of the frame shares (either backend).
    rtgi::FrameSetup frameSetup(PassContext& ctx) const;
};

}  // namespace fp
