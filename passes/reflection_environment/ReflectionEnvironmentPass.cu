// ReflectionEnvironmentPass on the GPU: reflection_environment::run with device images, one
// thread per pixel; the sky's and the captures' cubes and the EnvBRDF table copied for the frame.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/reflection_environment/ReflectionEnvironmentKernel.h"
#include "passes/reflection_environment/ReflectionEnvironmentPass.h"

namespace fp {

void ReflectionEnvironmentPass::executeCuda(PassContext& ctx) {
    reflection_environment::run(ctx, DevicePorts{ctx}, CudaPixels{}, lighting(ctx));
}

}  // namespace fp
