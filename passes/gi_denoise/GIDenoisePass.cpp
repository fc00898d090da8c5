#include "passes/gi_denoise/GIDenoisePass.h"

#include "foundation/PerPixel.h"
#include "framework/PassPorts.h"
#include "screenspace/SignalDenoiserKernel.h"

namespace fp {

namespace {
constexpr const char* kDiffuse = "diffuse";
constexpr const char* kAo = "ao";
}  // namespace

ParamSpec<GIDenoiseParams> GIDenoisePass::paramSpec() {
    return ssd::denoiserParamSpec<GIDenoiseParams>(
        {"r.DiffuseIndirect.Denoiser", "r.GlobalIllumination.Denoiser"});
}

PassIO GIDenoisePass::describe() const {
    PassIO io;
    io.inputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "raw GI radiance (rt_global_illumination.diffuse)"},
        {.name = kAo, .channels = {"Y"}, .doc = "raw GI AO (rt_global_illumination.ao)"},
    };
    for (PortSpec& p : ssd::denoiserInputs(ssd::Footprint::Diffuse))
        io.inputs.push_back(std::move(p));
    io.outputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "denoised radiance"},
        {.name = kAo, .channels = {"Y"}, .doc = "denoised AO"},
    };
    io.needsCamera = true;
    io.temporal = mParams.denoiser > 0 && mParams.temporalAccumulation;
    return io;
}

ssd::Denoising GIDenoisePass::denoising() const {
    // 4096: TARGETED_SAMPLE_COUNT of the diffuse-and-AO signal (§12.5).
    return {ssd::stagesOf(mParams, ssd::Footprint::Diffuse, 4096.0f), {kDiffuse, kAo},
            mParams.denoiser > 0};
}

void GIDenoisePass::execute(PassContext& ctx) {
    ssd::run(ctx, HostPorts{ctx}, CpuPixels{}, denoising());
}

}  // namespace fp
