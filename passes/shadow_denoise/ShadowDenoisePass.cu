// ShadowDenoisePass on the GPU: shadow_denoise::run with device images, one thread per pixel (per
// row and per column for the occluder table).
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/shadow_denoise/ShadowDenoiseKernel.h"
#include "passes/shadow_denoise/ShadowDenoisePass.h"
#include "shading/NamedLight.h"

namespace fp {

void ShadowDenoisePass::executeCuda(PassContext& ctx) {
    shadow_denoise::run(ctx, DevicePorts{ctx}, CudaPixels{}, namedLight(ctx.lights(), mParams.light),
                        mParams.denoiser, mParams.reconstructionSamples, mParams.preConvolution,
                        mParams.maxRadius);
}

}  // namespace fp
