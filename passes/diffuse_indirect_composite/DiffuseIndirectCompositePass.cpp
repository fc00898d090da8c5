#include "passes/diffuse_indirect_composite/DiffuseIndirectCompositePass.h"

#include "screenspace/GBuffer.h"
#include "framework/PassPorts.h"
#include "foundation/PerPixel.h"
#include "passes/diffuse_indirect_composite/DiffuseIndirectCompositeKernel.h"

namespace fp {

ParamSpec<DiffuseIndirectCompositeParams> DiffuseIndirectCompositePass::paramSpec() {
    ParamSpec<DiffuseIndirectCompositeParams> s;
    s.add("engine", &Params::engine,
          "ue4.27: SceneColor×AO + DiffuseColor×SSGI, point upsample; ue5: per-shading-model "
          "diffuse terms and a depth-tested 2×2 upsample")
        .choices({"ue4.27", "ue5"});
    s.add("aoStaticFraction", &Params::aoStaticFraction,
          "post-process AmbientOcclusionStaticFraction: how much of the AO darkens scene colour")
        .range(0.0, 1.0);
    return s;
}

PassIO DiffuseIndirectCompositePass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::sceneColorInput(composite::kSceneColor,
                                 "emissive + precomputed light before direct lighting"),
        gbuffer::baseColorInput(),
        gbuffer::metallicInput("metalness"),
        gbuffer::shadingModelInput("shading model id"),
        gbuffer::gbufferAOInput(false),
        {.name = composite::kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "denoised SSGI radiance (trace resolution)"},
        {.name = composite::kAo, .channels = {"Y"}, .doc = "denoised SSGI AO"},
    };
    if (ue5()) {
        io.inputs.push_back(
            gbuffer::customDataInput("subsurface / fuzz colour (√) and amounts", false));
        io.inputs.push_back(gbuffer::depthInput("depth for the half-resolution upsample test"));
    }
    io.outputs = {{.name = composite::kColor,
                   .channels = {"R", "G", "B"},
                   .kind = PortKind::Color,
                   .doc = "scene colour with diffuse indirect and AO applied"}};
    io.needsCamera = ue5();
    return io;
}

void DiffuseIndirectCompositePass::execute(PassContext& ctx) {
    composite::run(ctx, HostPorts{ctx}, CpuPixels{}, ue5(), mParams.aoStaticFraction);
}

}  // namespace fp
