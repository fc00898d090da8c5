// SSGIDenoisePass on the GPU: ssgi_denoise::run with device images; the history stays on the GPU.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/ssgi_denoise/SSGIDenoiseKernel.h"
#include "passes/ssgi_denoise/SSGIDenoisePass.h"

namespace fp {

void SSGIDenoisePass::executeCuda(PassContext& ctx) {
    ssgi_denoise::run(ctx, DevicePorts{ctx}, CudaPixels{}, mParams.denoiser,
                      mParams.temporalAccumulation, mParams.halfRes);
}

}  // namespace fp
