#pragma once
// ★ framepass's own, not one of Unreal's passes: screen-space reflections that fall back to the
// scene (algorithms §12.3). Every ray is SSR's — drawn, marched through the HZB and, where it hits
// on screen, read from last frame's colour exactly as `ssr` does. A ray the march cannot finish
// (it leaves the screen or ends without a hit) is traced through the scene's geometry in the same
// direction and its hit lit as `rt_reflections` lights one (the lights with shadow rays, the
// hit's emission, the sky's SH), or the sky's cubemap on a miss. The reverse of Unreal's
// r.RayTracing.Reflections.Hybrid, which traces first. The fallback rays go through Embree, or
// through framepass's own BVH (traversal "bvh": the GPU's code, which the GPU runs).
#include "framework/Params.h"
#include "framework/Pass.h"
#include "passes/ssr/SSRPass.h"
#include "shading/ReflectionHits.h"

#include <memory>
#include <string>

namespace fp {

struct HybridReflectionsParams : SSRParams {
    float normalBias = 0.1f;  //!< cm (min 0.01): a fallback ray's origin, as rt_reflections'
    int shadows = 1;          //!< 0: the fallback hits' lights unshadowed
    int hitIndirectBounces = 0;  //!< as rt_reflections'
    std::string traversal = "embree";  //!< the fallback rays': "embree" or "bvh" (the GPU's code)
};

struct BvhTracer;
namespace rtr {
struct Sky;
}
namespace hybrid_reflections {
template <class Tracer>
struct SceneFallback;
}

class HybridReflectionsPass final : public PassWithParams<HybridReflectionsParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    PassMemory memoryBytes(Extent frame) const override;

#if FP_HAVE_CUDA
    /// The GPU's paths read no sky: a hit's traced indirect light keeps the pass on the CPU.
    bool hasCudaKernel() const override { return mParams.hitIndirectBounces == 0; }
    void executeCuda(PassContext& ctx) override;  // HybridReflectionsPass.cu
#endif

private:
    /// The fallback through `tracer` (framepass's BVH and the lights where the pixels run) and
    /// `sky`, counting into `counts` (hybrid_reflections::FallbackCounter, where the pixels run).
    hybrid_reflections::SceneFallback<BvhTracer> bvhFallback(PassContext& ctx, const BvhTracer& tracer,
                                                             const rtr::Sky& sky,
                                                             unsigned long long* counts);
    void addFallbackWork(PassContext& ctx, const unsigned long long* counts) const;
    std::shared_ptr<const ReflectedSky> mSky;  // made once per sky light
};

}  // namespace fp
