// RTShadowsPass on the GPU: shadow::run with device images and the scene's BVH in device memory,
// one thread per pixel.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/rt_shadows/RTShadowsKernel.h"
#include "passes/rt_shadows/RTShadowsPass.h"

namespace fp {

void RTShadowsPass::executeCuda(PassContext& ctx) {
    // A warp traces 8×4 neighbouring pixels' rays (CudaLaunch.cuh's PixelBlock).
    shadow::run(ctx, DevicePorts{ctx}, CudaPixels{cuda::PixelBlock::Squares},
                shadow::setupFrame(mParams, ctx));
}

}  // namespace fp
