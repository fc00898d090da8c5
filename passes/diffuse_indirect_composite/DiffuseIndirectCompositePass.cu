// DiffuseIndirectCompositePass on the GPU: composite::run with device images.
#include "passes/core/CudaLaunch.cuh"
#include "passes/core/PassPorts.h"
#include "passes/diffuse_indirect_composite/DiffuseIndirectCompositeKernel.h"

namespace fp {

void DiffuseIndirectCompositePass::executeCuda(PassContext& ctx) {
    composite::run(ctx, DevicePorts{ctx}, CudaPixels{}, ue5(), mParams.aoStaticFraction);
}

}  // namespace fp
