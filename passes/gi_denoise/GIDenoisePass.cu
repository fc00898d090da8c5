// GIDenoisePass on the GPU: ssd::run with device images; the history stays on the GPU.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/gi_denoise/GIDenoisePass.h"
#include "screenspace/SignalDenoiserKernel.h"

namespace fp {

void GIDenoisePass::executeCuda(PassContext& ctx) {
    ssd::run(ctx, DevicePorts{ctx}, CudaPixels{}, denoising());
}

}  // namespace fp
