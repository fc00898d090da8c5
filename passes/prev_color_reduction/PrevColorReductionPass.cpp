#include "passes/prev_color_reduction/PrevColorReductionPass.h"

#include "screenspace/GBuffer.h"
#include "framework/PassPorts.h"
#include "foundation/PerPixel.h"
#include "passes/prev_color_reduction/PrevColorReductionKernel.h"

namespace fp {

ParamSpec<PrevColorReductionParams> PrevColorReductionPass::paramSpec() {
    ParamSpec<PrevColorReductionParams> s;
    s.add("leakFree", &Params::leakFree,
          "reproject previous colour + depth with leak-free weights (true) or bilinear TAA "
          "history (false) (algorithms §3.1)")
        .cvar("r.SSGI.LeakFreeReprojection");
    s.add("preExposureCorrection", &Params::preExposureCorrection,
          "PreExposure(current)/PreExposure(previous) applied to the previous colour")
        .range(0.0, 1e6);
    s.add("removeSky", &Params::removeSky,
          "zero colour whose current depth exceeds skyDistance (UE5 behaviour; 4.27 keeps it)");
    s.add("skyDistance", &Params::skyDistance, "Unreal's SSGI sky distance, scene units")
        .range(0.0, 1e30);
    return s;
}

PassIO PrevColorReductionPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::depthInput("current linear depth"),
        gbuffer::velocityInput("optional per-pixel motion; camera reprojection when unbound"),
        {.name = prev_color::kFurthestHzb,
         .channels = {"Z"},
         .doc = "furthest HZB: reference depth of the lower mips"},
    };
    if (mParams.leakFree) {
        io.inputs.push_back({.name = prev_color::kPrevColor,
                             .channels = {"R", "G", "B"},
                             .kind = PortKind::Color,
                             .captureDefault = "PrevSceneColor",
                             .doc = "last frame's scene colour"});
        io.inputs.push_back({.name = prev_color::kPrevDepth,
                             .channels = {"Z"},
                             .captureDefault = "PrevSceneDepth",
                             .doc = "last frame's linear depth"});
    } else {
        io.inputs.push_back({.name = prev_color::kHistory,
                             .channels = {"R", "G", "B"},
                             .kind = PortKind::Color,
                             .captureDefault = "TAAHistory",
                             .doc = "last frame's TAA history"});
    }
    io.outputs = {
        {.name = prev_color::kColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "reduced colour, premultiplied by the leak-free weight, 5 mips"},
        {.name = prev_color::kAlpha, .channels = {"A"}, .doc = "accumulated leak-free weight, 5 mips"}};
    io.needsCamera = true;
    return io;
}

std::vector<Extent> PrevColorReductionPass::mipExtents(Extent frame) {
    auto roundUp16 = [](int v) { return (v + 15) / 16 * 16; };
    return mipChain({roundUp16((frame.width + 1) / 2), roundUp16((frame.height + 1) / 2)},
                    kMipCount);
}

std::vector<Extent> PrevColorReductionPass::outputExtents(std::string_view, Extent frame) const {
    return mipExtents(frame);
}

PassMemory PrevColorReductionPass::memoryBytes(Extent frame) const {
    // The kernel reduces into one 5-channel chain (colour, weight, depth) before its outputs.
    return {imageBytes(mipExtents(frame), 5), 0};
}

void PrevColorReductionPass::execute(PassContext& ctx) {
    prev_color::run(ctx, HostPorts{ctx}, CpuPixels{}, mParams);
}

}  // namespace fp
