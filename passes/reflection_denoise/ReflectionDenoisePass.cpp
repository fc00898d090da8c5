#include "passes/reflection_denoise/ReflectionDenoisePass.h"

#include "foundation/PerPixel.h"
#include "framework/PassPorts.h"
#include "screenspace/SignalDenoiserKernel.h"

namespace fp {

namespace {
constexpr const char* kReflection = "reflection";
}  // namespace

ParamSpec<ReflectionDenoiseParams> ReflectionDenoisePass::paramSpec() {
    return ssd::denoiserParamSpec<ReflectionDenoiseParams>(
        {"r.Reflections.Denoiser", "r.Reflections.Denoiser"});
}

PassIO ReflectionDenoisePass::describe() const {
    PassIO io;
    io.inputs = {{.name = kReflection,
                  .channels = {"R", "G", "B", "A"},
                  .kind = PortKind::Color,
                  .doc = "raw reflections, coverage in A (rt_reflections.reflection)"}};
    for (PortSpec& p : ssd::denoiserInputs(ssd::Footprint::Specular))
        io.inputs.push_back(std::move(p));
    io.outputs = {{.name = kReflection,
                   .channels = {"R", "G", "B", "A"},
                   .kind = PortKind::Color,
                   .doc = "denoised reflections, coverage in A: for reflection_environment"}};
    io.needsCamera = true;
    io.temporal = mParams.denoiser > 0 && mParams.temporalAccumulation;
    return io;
}

ssd::Denoising ReflectionDenoisePass::denoising() const {
    // 128: not read for reflections; SSGI's, a short history (§12.5). Unreal's reflections have
    // no history convolution.
    return {ssd::stagesOf(mParams, ssd::Footprint::Specular, 128.0f), {kReflection},
            mParams.denoiser > 0};
}

void ReflectionDenoisePass::execute(PassContext& ctx) {
    ssd::run(ctx, HostPorts{ctx}, CpuPixels{}, denoising());
}

}  // namespace fp
