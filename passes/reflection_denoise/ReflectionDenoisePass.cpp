#include "passes/reflection_denoise/ReflectionDenoisePass.h"

#include "screenspace/SignalDenoiser.h"

namespace fp {

namespace {
constexpr const char* kReflection = "reflection";
}  // namespace

ParamSpec<ReflectionDenoiseParams> ReflectionDenoisePass::paramSpec() {
    ParamSpec<ReflectionDenoiseParams> s;
    s.add("denoiser", &Params::denoiser, "0 passes the raw reflections through; 1 (and 2) denoise")
        .range(0, 2)
        .cvar("r.Reflections.Denoiser");
    s.add("reconstructionSamples", &Params::reconstructionSamples,
          "taps of the spatial reconstruction (1–56)")
        .range(1, 56)
        .cvar("r.Reflections.Denoiser.ReconstructionSamples");
    s.add("preConvolution", &Params::preConvolution, "8-tap pre-convolution passes after it")
        .range(0, 8)
        .cvar("r.Reflections.Denoiser.PreConvolution");
    s.add("temporalAccumulation", &Params::temporalAccumulation, "accumulate across frames")
        .needsHistory()
        .cvar("r.Reflections.Denoiser.TemporalAccumulation");
    return s;
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

void ReflectionDenoisePass::execute(PassContext& ctx) {
    ssd::Stages stages;
    stages.footprint = ssd::Footprint::Specular;
    stages.reconstructionSamples = mParams.reconstructionSamples;
    stages.preConvolutions = mParams.preConvolution;
    stages.temporalAccumulation = mParams.temporalAccumulation;
    stages.targetSamples = 128.0f;  // not read for reflections: SSGI's, a short history (§12.5)
    stages.historyConvolutionSamples = 0;  // Unreal's reflections have no history convolution
    ssd::denoisePorts(ctx, stages, {kReflection}, mParams.denoiser > 0);
}

}  // namespace fp
