// SSRPass on the GPU: ssr::run with device images, one thread per pixel; the temporal history
// stays on the GPU.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/ssr/SSRKernel.h"
#include "passes/ssr/SSRPass.h"

namespace fp {

void SSRPass::executeCuda(PassContext& ctx) {
    ssr::run(ctx, DevicePorts{ctx}, CudaPixels{},
             ssr::effectiveQuality(mParams.quality, mParams.postProcessQuality, mParams.intensity),
             mParams.maxRoughness, mParams.intensity, mParams.temporal);
}

}  // namespace fp
