#include "passes/camera_velocity/CameraVelocityPass.h"

#include "framework/PassPorts.h"
#include "passes/camera_velocity/CameraVelocityKernel.h"
#include "screenspace/GBuffer.h"

namespace fp {

namespace {
using camera_velocity::kVelocity;
}  // namespace

ParamSpec<CameraVelocityParams> CameraVelocityPass::paramSpec() {
    ParamSpec<CameraVelocityParams> s;
    s.add("skyDistance", &Params::skyDistance,
          "depths at or beyond this are sky and move by the camera's rotation only, scene units; "
          "0 = only +inf")
        .range(0.0, 1e30);
    return s;
}

PassIO CameraVelocityPass::describe() const {
    PassIO io;
    io.inputs = {gbuffer::depthInput()};
    io.outputs = {{.name = kVelocity,
                   .channels = {"X", "Y"},
                   .doc = "pixels from this pixel's centre to its surface on last frame's screen "
                          "(+Y down), as the capture's Velocity; a surface behind last frame's "
                          "camera points off screen"}};
    io.needsCamera = true;
    return io;
}

void CameraVelocityPass::execute(PassContext& ctx) {
    camera_velocity::run(ctx, HostPorts{ctx}, CpuPixels{}, mParams.skyDistance);
}

}  // namespace fp
