// HZBPass on the GPU: hzb::run with device images and one thread per texel.
#include "screenspace/GBuffer.h"
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/hzb/HZBKernel.h"
#include "passes/hzb/HZBPass.h"

namespace fp {

void HZBPass::executeCuda(PassContext& ctx) {
    const DeviceImage& depth = ctx.deviceInput(gbuffer::kDepth)->image();
    hzb::run(ctx, DevicePorts{ctx}, CudaPixels{}, mParams.halfPrecision,
             mipExtents({depth.width(), depth.height()}));
}

}  // namespace fp
