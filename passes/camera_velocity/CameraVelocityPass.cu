// CameraVelocityPass on the GPU: camera_velocity::run with device images, one thread per pixel.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/camera_velocity/CameraVelocityKernel.h"
#include "passes/camera_velocity/CameraVelocityPass.h"

namespace fp {

void CameraVelocityPass::executeCuda(PassContext& ctx) {
    camera_velocity::run(ctx, DevicePorts{ctx}, CudaPixels{}, mParams.skyDistance);
}

}  // namespace fp
