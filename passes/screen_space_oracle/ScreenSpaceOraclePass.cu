// ScreenSpaceOraclePass on the GPU: screen_space_oracle::run with device images, one thread per
// pixel and its rays.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/screen_space_oracle/ScreenSpaceOracleKernel.h"
#include "passes/screen_space_oracle/ScreenSpaceOraclePass.h"

namespace fp {

void ScreenSpaceOraclePass::executeCuda(PassContext& ctx) {
    screen_space_oracle::run(ctx, DevicePorts{ctx}, CudaPixels{}, mParams.rays, mParams.thickness,
                             mParams.aoRadius);
}

}  // namespace fp
