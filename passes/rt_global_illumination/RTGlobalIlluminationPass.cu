// RTGlobalIlluminationPass on the GPU: rtgi::run through framepass's BVH in device memory, the
// scene's lights copied with the frame, one thread per traced texel.
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
    // A warp traces 8×4 neighbouring texels' paths (CudaLaunch.cuh's PixelBlock), as rt_shadows.
    rtgi::run(ctx, ports, CudaPixels{cuda::PixelBlock::Squares}, frameSetup(ctx),
              outputExtents(rtgi::kDiffuse, ctx.frame().extent).front(), tracer,
              "rt_global_illumination");
}

}  // namespace fp
