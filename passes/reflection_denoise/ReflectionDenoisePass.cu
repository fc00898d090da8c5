// ReflectionDenoisePass on the GPU: ssd::run with device images; the history stays on the GPU.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/reflection_denoise/ReflectionDenoisePass.h"
#include "screenspace/SignalDenoiserKernel.h"

namespace fp {

void ReflectionDenoisePass::executeCuda(PassContext& ctx) {
    ssd::run(ctx, DevicePorts{ctx}, CudaPixels{}, denoising());
}

}  // namespace fp
