// PrevColorReductionPass on the GPU: prev_color::run with device images, a thread per texel.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/prev_color_reduction/PrevColorReductionKernel.h"

namespace fp {

void PrevColorReductionPass::executeCuda(PassContext& ctx) {
    prev_color::run(ctx, DevicePorts{ctx}, CudaPixels{}, mParams);
}

}  // namespace fp
