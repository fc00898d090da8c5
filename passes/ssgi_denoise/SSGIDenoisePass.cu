// SSGIDenoisePass on the GPU: ssgi_denoise::run with device images; the history stays on the GPU.
#include "passes/core/CudaLaunch.cuh"
#include "passes/core/PassPorts.h"
#include "passes/ssgi_denoise/SSGIDenoiseKernel.h"
#include "passes/ssgi_denoise/SSGIDenoisePass.h"

namespace fp {

void SSGIDenoisePass::executeCuda(PassContext& ctx) {
    ssgi_denoise::run(ctx, DevicePorts{ctx}, CudaPixels{}, mParams.denoiser,
                      mParams.temporalAccumulation, mParams.halfRes);
}

}  // namespace fp
