// HybridPass on the GPU: SSGI's kernel with the scene paths as its fallback, through framepass's
// BVH in device memory and the scene's lights copied with the frame; the fallback's counts summed
// on the GPU and read back once.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/hybrid/HybridKernel.h"
#include "passes/hybrid/HybridPass.h"
#include "passes/ssgi/SSGIPass.h"

namespace fp {

void HybridPass::executeCuda(PassContext& ctx) {
    const SSGIQuality q = SSGIPass::traced(mParams.quality, mParams.rays);
    const DevicePorts ports{ctx};
    const DirectLighting lighting(ctx.scene(), 1);
    std::shared_ptr<const LightView> lights;
    const cuda::SharedCounters counts(hybrid::kHybridCounters, "hybrid");
    hybrid::GiFallback<BvhTracer> fallback =
        bvhFallback(ctx, bvhTracerFor(ports, lighting, lights), counts.data());
    hybrid::bindPlanes(ports, fallback);
    const auto ssgiCounts =
        ssgi::run(ctx, ports, CudaPixels{}, q.rays, q.steps, false, 1.0f, fallback, "hybrid");
    addFallbackWork(ctx, ssgiCounts[ssgi::kRays], counts.totals().data());
}

}  // namespace fp
