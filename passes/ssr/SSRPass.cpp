#include "passes/ssr/SSRPass.h"

#include "framework/PassPorts.h"
#include "passes/ssr/SSRKernel.h"
#include "screenspace/GBuffer.h"

namespace fp {

namespace {
using ssr::kColor;
using ssr::kFurthestHzb;
using ssr::kHitDistance;
using ssr::kHitMask;
using ssr::kReflection;
}  // namespace

SSRQuality SSRPass::effectiveQuality(int cvar, int postProcessQuality, float intensity) {
    return ssr::effectiveQuality(cvar, postProcessQuality, intensity);
}

float SSRPass::roughnessFade(float roughness, float maxRoughness, int level) {
    return ssr::roughnessFade(roughness, maxRoughness, level);
}

PassIO SSRPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::depthInput("linear view depth"),
        gbuffer::normalInput(),
        gbuffer::roughnessInput("roughness: the fade, the rays' lobe and mip schedule"),
        gbuffer::shadingModelInput("shading model id (unlit skipped; clear coat blends roughness)"),
        gbuffer::customDataInput("clear coat amount and roughness (R, G)", true),
        {.name = kFurthestHzb, .channels = {"Y"}, .doc = "furthest HZB (hzb.furthest)"},
        {.name = kColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .captureDefault = "PrevSceneColor",
         .doc = "last frame's colour the hits read (Unreal reads its TAA history: bind "
                "capture:TAAHistory where the capture has one)"},
        gbuffer::velocityInput("the hit texel's motion to last frame (none: the cameras)"),
    };
    io.outputs = {
        {.name = kReflection, .channels = {"R", "G", "B", "A"}, .kind = PortKind::Color,
         .doc = "premultiplied reflected radiance × fade, A = coverage (mean vignette of the rays)"},
        {.name = kHitMask, .channels = {"Y"}, .doc = "debug: fraction of rays that hit"},
        {.name = kHitDistance, .channels = {"Y"}, .doc = "debug: mean distance to the hits, scene units (0: none)"},
    };
    io.needsCamera = true;
    io.workUnit = "hzbSamples";
    io.temporal = mParams.temporal;
    return io;
}

PassMemory SSRPass::memoryBytes(Extent frame) const {
    // r.SSR.Temporal: the traced colour becomes the history.
    const std::size_t traced = mParams.temporal ? imageBytes(frame, 4) : 0;
    return {traced, traced};
}

void SSRPass::execute(PassContext& ctx) {
    ssr::run(ctx, HostPorts{ctx}, CpuPixels{},
             ssr::effectiveQuality(mParams.quality, mParams.postProcessQuality, mParams.intensity),
             mParams.maxRoughness, mParams.intensity, mParams.temporal);
}

}  // namespace fp
