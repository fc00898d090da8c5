// SSGIPass on the GPU: ssgi::run with device images, one thread per trace pixel.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/ssgi/SSGIKernel.h"
#include "passes/ssgi/SSGIPass.h"

namespace fp {

void SSGIPass::executeCuda(PassContext& ctx) {
    const SSGIQuality q = traced(mParams.quality, mParams.rays);
    ssgi::run(ctx, DevicePorts{ctx}, CudaPixels{}, q.rays, q.steps, mParams.halfRes,
              mParams.indirectLightingColorScale);
}

}  // namespace fp
