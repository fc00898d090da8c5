// HybridReflectionsPass on the GPU: SSR's kernel with the fallback through framepass's BVH in
// device memory, the scene's lights and the sky light's cubemap copied with the frame; the
// fallback's counts summed on the GPU and read back once.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/hybrid_reflections/HybridReflectionsKernel.h"
#include "passes/hybrid_reflections/HybridReflectionsPass.h"

namespace fp {

void HybridReflectionsPass::executeCuda(PassContext& ctx) {
    using namespace hybrid_reflections;
    const DevicePorts ports{ctx};
    mSky = ReflectedSky::of(ctx.scene().scene().environment.sky, mSky);
    const DirectLighting lighting(ctx.scene(), 1);
    std::shared_ptr<const LightView> lights;
    std::shared_ptr<const Vec3f> cubeTexels;
    const rtr::Sky sky = rtr::skyFor(ports, mSky.get(), cubeTexels);
    const cuda::SharedCounters counts(kFallbackCounters, "hybrid_reflections");
    runSsr(ctx, ports, CudaPixels{}, mParams,
           bvhFallback(ctx, bvhTracerFor(ports, lighting, lights), sky, counts.data()));
    addFallbackWork(ctx, counts.totals().data());
}

}  // namespace fp
