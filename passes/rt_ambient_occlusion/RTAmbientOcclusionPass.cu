// RTAmbientOcclusionPass on the GPU: rtao::run with device images and the scene's BVH in device
// memory, one thread per pixel.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/rt_ambient_occlusion/RTAmbientOcclusionKernel.h"
#include "passes/rt_ambient_occlusion/RTAmbientOcclusionPass.h"

namespace fp {

void RTAmbientOcclusionPass::executeCuda(PassContext& ctx) {
    // A warp traces 8×4 neighbouring pixels' rays (CudaLaunch.cuh's PixelBlock), as rt_shadows.
    rtao::run(ctx, DevicePorts{ctx}, CudaPixels{cuda::PixelBlock::Squares}, frameSetup(ctx));
}

}  // namespace fp
