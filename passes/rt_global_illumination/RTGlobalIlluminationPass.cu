// RTGlobalIlluminationPass on the GPU: rtgi::run through framepass's BVH in device memory, the
// scene's lights copied with the frame, each thread taking texels until none is left.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/rt_global_illumination/RTGlobalIlluminationKernel.h"
#include "passes/rt_global_illumination/RTGlobalIlluminationPass.h"

namespace fp {

void RTGlobalIlluminationPass::executeCuda(PassContext& ctx) {
    const DevicePorts ports{ctx};
    const DirectLighting lighting(ctx.scene(), 1);
    std::shared_ptr<const LightView> lights;
    const BvhTracer tracer = bvhTracerFor(ports, lighting, lights);
    // forEachInSteps: a thread whose texel is done takes the next (a warp's first 32 texels an
    // 8×4 square, as rt_shadows' PixelBlock::Squares), so a warp does not wait for its longest.
    rtgi::run(ctx, ports, CudaPixels{}, frameSetup(ctx),
              outputExtents(rtgi::kDiffuse, ctx.frame().extent).front(), tracer,
              "rt_global_illumination");
}

}  // namespace fp
