// RTShadowsPass on the GPU: shadow::run with device images and the scene's BVH in device memory,
// one thread per pixel.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/rt_shadows/RTShadowsKernel.h"
#include "passes/rt_shadows/RTShadowsPass.h"

namespace fp {

void RTShadowsPass::executeCuda(PassContext& ctx) {
    shadow::run(ctx, DevicePorts{ctx}, CudaPixels{}, shadow::setupFrame(mParams, ctx));
}

}  // namespace fp
