// DiffuseIndirectCompositePass on the GPU: composite::run with device images.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/diffuse_indirect_composite/DiffuseIndirectCompositeKernel.h"

namespace fp {

void DiffuseIndirectCompositePass::executeCuda(PassContext& ctx) {
    composite::run(ctx, DevicePorts{ctx}, CudaPixels{}, ue5(), mParams.aoStaticFraction);
}

}  // namespace fp
