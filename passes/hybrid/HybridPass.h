#pragma once
// ★ framepass's own, not one of Unreal's passes: screen-space GI that falls back to the scene
// (algorithms §12.3). Every ray is SSGI's — drawn, marched through the HZB and, where it hits on
// screen, shaded from last frame's colour exactly as `ssgi` does. A ray the march cannot finish
// (it leaves the screen, passes behind surfaces, or ends without a hit) is traced again through
// the scene's geometry and its hit shaded as `rt_global_illumination` shades one: the lights
// sampled with shadow rays, no emission, `maxBounces` diffuse bounces. Lumen's screen traces
// before its ray-traced fallback are the precedent. With `continueOnScreen`, an on-screen hit
// also continues as a scene path for the bounces last frame's colour lacks, where that colour
// holds direct light only (a capture's). SSGI's own kernel runs every ray (ssgi::run), handed
// the scene paths as its fallback (HybridKernel.h), through Embree or through framepass's own
// BVH (traversal "bvh": the GPU's code, which the GPU runs).
#include "framework/Params.h"
#include "framework/Pass.h"

#include <cstdint>
#include <string>

namespace fp {

struct HybridParams {
    int quality = 4;        //!< r.SSGI.Quality: the screen rays' count and steps
    int rays = 0;           //!< rays per pixel in place of the quality's (0: the quality's)
    int maxBounces = 1;     //!< hits a fallback path shades
    int nextEventEstimationSamples = 2;  //!< light samples at each fallback hit
    float normalBias = 0.1f;  //!< cm (min 0.01): the fallback ray's origin, as the RT passes
    bool continueOnScreen = false;  //!< on-screen hits continue as paths of maxBounces − 1
    std::string traversal = "embree";  //!< the scene paths': "embree" or "bvh" (the GPU's code)
    bool waves = true;  //!< Embree: a tile's scene paths a step at a time, in packets
};

struct BvhTracer;
struct EmbreeTracer;
struct DiffusePathSetup;
struct HostPorts;
namespace hybrid {
template <class Tracer>
struct GiFallback;
}

class HybridPass final : public PassWithParams<HybridParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

    FP_PASS_HAS_CUDA_KERNEL  // HybridPass.cu

private:
    /// The fallback through `tracer` (framepass's BVH and the lights where the pixels run),
    /// counting into `counts` (hybrid::HybridCounter, where the pixels run); its planes not yet
    /// bound.
    hybrid::GiFallback<BvhTracer> bvhFallback(PassContext& ctx, const BvhTracer& tracer,
                                              unsigned long long* counts) const;
    /// SSGI's kernel over each tile, recording its march (HybridMarch.h): each ray's light in
    /// order and what it asks of the scene (`fallback`'s paths: `missSetup`'s for a ray the
    /// screen cannot finish, `onwardSetup`'s for an on-screen hit's continuation); the paths run
    /// a step at a time in Embree's packets (DiffusePathWave), then each pixel is summed from the
    /// record with what they brought: ssgi::run's outputs and work, the same bits; SSGI's ray
    /// count.
    uint64_t traceWaves(PassContext& ctx, const HostPorts& ports, int rays, int steps,
                        const hybrid::GiFallback<EmbreeTracer>& fallback,
                        const DiffusePathSetup& missSetup,
                        const DiffusePathSetup& onwardSetup) const;
    /// The fallback's counts, with `rays` (SSGI's count, on screen and not) for the on-screen ones.
    void addFallbackWork(PassContext& ctx, uint64_t rays, const unsigned long long* counts) const;
};

}  // namespace fp
