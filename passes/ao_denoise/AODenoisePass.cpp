#include "passes/ao_denoise/AODenoisePass.h"

#include "screenspace/SignalDenoiser.h"

namespace fp {

namespace {
constexpr const char* kAo = "ao";
}  // namespace

ParamSpec<AODenoiseParams> AODenoisePass::paramSpec() {
    ParamSpec<AODenoiseParams> s;
    s.add("denoiser", &Params::denoiser, "0 passes the raw mask through; 1 (and 2) denoise")
        .range(0, 2)
        .cvar("r.AmbientOcclusion.Denoiser");
    s.add("reconstructionSamples", &Params::reconstructionSamples,
          "taps of the spatial reconstruction (Unreal clamps them to 1–56)")
        .range(1, 56)
        .cvar("r.AmbientOcclusion.Denoiser.ReconstructionSamples");
    s.add("preConvolution", &Params::preConvolution, "8-tap pre-convolution passes after it")
        .range(0, 8)
        .cvar("r.AmbientOcclusion.Denoiser.PreConvolution");
    s.add("temporalAccumulation", &Params::temporalAccumulation, "accumulate across frames")
        .needsHistory()
        .cvar("r.AmbientOcclusion.Denoiser.TemporalAccumulation");
    s.add("historyConvolutionSamples", &Params::historyConvolutionSamples,
          "taps of the history convolution, the post filter after the accumulation (0: none)")
        .range(0, 56)
        .cvar("r.AmbientOcclusion.Denoiser.HistoryConvolution.SampleCount");
    s.add("historyConvolutionSpread", &Params::historyConvolutionSpread,
          "the history convolution's radius, pixels")
        .range(0.0, 64.0)
        .cvar("r.AmbientOcclusion.Denoiser.HistoryConvolution.KernelSpreadFactor");
    return s;
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

void AODenoisePass::execute(PassContext& ctx) {
    ssd::Stages stages;
    stages.footprint = ssd::Footprint::Diffuse;
    stages.reconstructionSamples = mParams.reconstructionSamples;
    stages.preConvolutions = mParams.preConvolution;
    stages.temporalAccumulation = mParams.temporalAccumulation;
    stages.targetSamples = 4096.0f;  // as the diffuse-and-AO signal's (§12.5: not read for AO)
    stages.historyConvolutionSamples = mParams.historyConvolutionSamples;
    stages.historyConvolutionSpread = mParams.historyConvolutionSpread;
    ssd::denoisePorts(ctx, stages, {kAo}, mParams.denoiser > 0);
}

}  // namespace fp
