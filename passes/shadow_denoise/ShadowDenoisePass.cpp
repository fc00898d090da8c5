#include "passes/shadow_denoise/ShadowDenoisePass.h"

#include "framework/PassPorts.h"
#include "passes/shadow_denoise/ShadowDenoiseKernel.h"
#include "screenspace/GBuffer.h"
#include "shading/NamedLight.h"

namespace fp {

namespace {
using shadow_denoise::kHitDistance;
using shadow_denoise::kLightAttenuation;
using shadow_denoise::kShadow;
using shadow_denoise::kTransmission;
}  // namespace

ParamSpec<ShadowDenoiseParams> ShadowDenoisePass::paramSpec() {
    ParamSpec<ShadowDenoiseParams> s;
    s.add("denoiser", &Params::denoiser,
          "0 off (raw shadow), 1 or 2 on (2, a third-party denoiser in Unreal, runs framepass's) "
          "(algorithms §6.3)")
        .range(0, 2)
        .cvar("r.Shadow.Denoiser");
    s.add("light", &Params::light, "name of the light (\"\" = the scene's only light)");
    s.add("reconstructionSamples", &Params::reconstructionSamples, "taps of each filtering pass")
        .range(1, 64)
        .cvar("r.Shadow.Denoiser.ReconstructionSamples");
    s.add("preConvolution", &Params::preConvolution, "filtering passes before the reconstruction")
        .range(0, 4)
        .cvar("r.Shadow.Denoiser.PreConvolution");
    s.add("maxRadius", &Params::maxRadius, "largest blur radius, pixels").range(0.0, 256.0);
    return s;
}

PassIO ShadowDenoisePass::describe() const {
    PassIO io;
    io.inputs = {
        {.name = kShadow, .channels = {"Y"}, .doc = "raw visibility"},
        {.name = kTransmission, .channels = {"Y"}, .doc = "raw subsurface term"},
        {.name = kHitDistance, .channels = {"Y"}, .doc = "closest occluder distance (−1 = none)"},
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit and sky pixels are neither filtered nor used"),
    };
    io.outputs = {
        {.name = kShadow, .channels = {"Y"}, .doc = "filtered visibility"},
        {.name = kTransmission, .channels = {"Y"}, .doc = "filtered subsurface term"},
        {.name = kLightAttenuation,
         .channels = {"R", "G", "B", "A"},
         .doc = "Unreal's light-attenuation encoding of the filtered result (algorithms §9.5)"},
    };
    io.needsCamera = true;
    io.needsLights = true;  // the light's size and position
    return io;
}

PassMemory ShadowDenoisePass::memoryBytes(Extent frame) const {
    return shadow_denoise::memoryOf(frame, mParams.denoiser);
}

void ShadowDenoisePass::execute(PassContext& ctx) {
    shadow_denoise::run(ctx, HostPorts{ctx}, CpuPixels{}, namedLight(ctx.lights(), mParams.light),
                        mParams.denoiser, mParams.reconstructionSamples, mParams.preConvolution,
                        mParams.maxRadius);
}

}  // namespace fp
