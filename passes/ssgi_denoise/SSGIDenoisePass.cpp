#include "passes/ssgi_denoise/SSGIDenoisePass.h"

#include "screenspace/GBuffer.h"
#include "screenspace/TraceResolution.h"
#include "framework/PassPorts.h"
#include "foundation/PerPixel.h"
#include "passes/ssgi_denoise/SSGIDenoiseKernel.h"

namespace fp {

namespace {
using ssgi_denoise::kAo;
using ssgi_denoise::kDiffuse;
using ssgi_denoise::kHistoryValidity;
}  // namespace

ParamSpec<SSGIDenoiseParams> SSGIDenoisePass::paramSpec() {
    ParamSpec<SSGIDenoiseParams> s;
    s.add("denoiser", &Params::denoiser,
          "0 passes the raw trace through; 1 (and 2, a third-party denoiser in Unreal) run "
          "framepass's")
        .range(0, 2)
        .cvar("r.DiffuseIndirect.Denoiser");
    s.add("temporalAccumulation", &Params::temporalAccumulation, "accumulate across frames")
        .needsHistory()
        .cvar("r.GlobalIllumination.Denoiser.TemporalAccumulation");
    s.add("halfRes", &Params::halfRes,
          "the SSGI trace ran at half resolution: the denoiser runs at the trace resolution (the "
          "same cvars set ssgi.halfRes)")
        .cvar("r.SSGI.HalfRes")
        .cvar("r.DiffuseIndirect.HalfRes");
    return s;
}

PassIO SSGIDenoisePass::describe() const {
    PassIO io;
    io.inputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "raw SSGI radiance"},
        {.name = kAo, .channels = {"Y"}, .doc = "raw SSGI AO"},
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit (0) pixels are left as they are"),
        gbuffer::velocityInput(
            "optional motion for reprojection; the history's camera is used when unbound"),
    };
    io.outputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "denoised radiance"},
        {.name = kAo, .channels = {"Y"}, .doc = "denoised AO"},
        {.name = kHistoryValidity,
         .channels = {"Y"},
         .doc = "debug: share of last frame's history kept (0 = none: first frame, cut, "
                "disocclusion)"},
    };
    io.needsCamera = true;
    io.temporal = mParams.denoiser > 0 && mParams.temporalAccumulation;
    return io;
}

std::vector<Extent> SSGIDenoisePass::outputExtents(std::string_view, Extent frame) const {
    return {traceExtent(frame, mParams.halfRes)};
}

PassMemory SSGIDenoisePass::memoryBytes(Extent frame) const {
    return ssgi_denoise::memoryOf(traceExtent(frame, mParams.halfRes), mParams.denoiser,
                                  mParams.temporalAccumulation);
}

void SSGIDenoisePass::execute(PassContext& ctx) {
    ssgi_denoise::run(ctx, HostPorts{ctx}, CpuPixels{}, mParams.denoiser,
                      mParams.temporalAccumulation, mParams.halfRes);
}

}  // namespace fp
