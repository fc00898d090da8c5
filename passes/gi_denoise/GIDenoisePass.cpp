#include "passes/gi_denoise/GIDenoisePass.h"

#include "screenspace/SignalDenoiser.h"

namespace fp {

namespace {
constexpr const char* kDiffuse = "diffuse";
constexpr const char* kAo = "ao";
}  // namespace

ParamSpec<GIDenoiseParams> GIDenoisePass::paramSpec() {
    ParamSpec<GIDenoiseParams> s;
    s.add("denoiser", &Params::denoiser, "0 passes the raw trace through; 1 (and 2) denoise")
        .range(0, 2)
        .cvar("r.DiffuseIndirect.Denoiser");
    s.add("reconstructionSamples", &Params::reconstructionSamples,
          "taps of the spatial reconstruction (Unreal clamps them to 1–56)")
        .range(1, 56)
        .cvar("r.GlobalIllumination.Denoiser.ReconstructionSamples");
    s.add("preConvolution", &Params::preConvolution, "8-tap pre-convolution passes after it")
        .range(0, 8)
        .cvar("r.GlobalIllumination.Denoiser.PreConvolution");
    s.add("temporalAccumulation", &Params::temporalAccumulation, "accumulate across frames")
        .needsHistory()
        .cvar("r.GlobalIllumination.Denoiser.TemporalAccumulation");
    s.add("historyConvolutionSamples", &Params::historyConvolutionSamples,
          "taps of the history convolution, the post filter after the accumulation (0: none)")
        .range(0, 56)
        .cvar("r.GlobalIllumination.Denoiser.HistoryConvolution.SampleCount");
    s.add("historyConvolutionSpread", &Params::historyConvolutionSpread,
          "the history convolution's radius, pixels")
        .range(0.0, 64.0)
        .cvar("r.GlobalIllumination.Denoiser.HistoryConvolution.KernelSpreadFactor");
    return s;
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

void GIDenoisePass::execute(PassContext& ctx) {
    ssd::Stages stages;
    stages.footprint = ssd::Footprint::Diffuse;
    stages.reconstructionSamples = mParams.reconstructionSamples;
    stages.preConvolutions = mParams.preConvolution;
    stages.temporalAccumulation = mParams.temporalAccumulation;
    stages.targetSamples = 4096.0f;  // TARGETED_SAMPLE_COUNT of the diffuse-and-AO signal (§12.5)
    stages.historyConvolutionSamples = mParams.historyConvolutionSamples;
    stages.historyConvolutionSpread = mParams.historyConvolutionSpread;
    ssd::denoisePorts(ctx, stages, {kDiffuse, kAo}, mParams.denoiser > 0);
}

}  // namespace fp
