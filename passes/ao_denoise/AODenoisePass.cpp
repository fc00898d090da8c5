#include "passes/ao_denoise/AODenoisePass.h"

#include "foundation/PerPixel.h"
#include "framework/PassPorts.h"
#include "screenspace/SignalDenoiserKernel.h"

namespace fp {

namespace {
constexpr const char* kAo = "ao";
}  // namespace

ParamSpec<AODenoiseParams> AODenoisePass::paramSpec() {
    return ssd::denoiserParamSpec<AODenoiseParams>(
        {"r.AmbientOcclusion.Denoiser", "r.AmbientOcclusion.Denoiser"});
}

PassIO AODenoisePass::describe() const {
    PassIO io;
    io.inputs = {{.name = kAo, .channels = {"Y"}, .doc = "raw AO mask (rt_ambient_occlusion.ao)"}};
    for (PortSpec& p : ssd::denoiserInputs(ssd::Footprint::Diffuse))
        io.inputs.push_back(std::move(p));
    io.outputs = {{.name = kAo, .channels = {"Y"}, .doc = "denoised AO"}};
    io.needsCamera = true;
    io.temporal = mParams.denoiser > 0 && mParams.temporalAccumulation;
    return io;
}

ssd::Denoising AODenoisePass::denoising() const {
    // 4096, as the diffuse-and-AO signal's (§12.5: not read for AO).
    return {ssd::stagesOf(mParams, ssd::Footprint::Diffuse, 4096.0f), {kAo}, mParams.denoiser > 0};
}

void AODenoisePass::execute(PassContext& ctx) {
    ssd::run(ctx, HostPorts{ctx}, CpuPixels{}, denoising());
}

}  // namespace fp
