#include "passes/hzb/HZBPass.h"

#include "screenspace/GBuffer.h"
#include "framework/PassPorts.h"
#include "foundation/PerPixel.h"
#include "passes/hzb/HZBKernel.h"

#include <algorithm>
#include <bit>

namespace fp {

namespace {
int ceilLog2(int v) {
    return v <= 1 ? 0 : int(std::bit_width(unsigned(v - 1)));
}
}  // namespace

ParamSpec<HZBParams> HZBPass::paramSpec() {
    ParamSpec<HZBParams> s;
    s.add("halfPrecision", &HZBParams::halfPrecision,
          "round device Z to half precision, as Unreal's PF_R16F HZB does");
    return s;
}

PassIO HZBPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::depthInput("linear view depth (converted to reversed device Z with the camera)")};
    io.outputs = {
        {.name = hzb::kFurthest, .channels = {"Z"}, .doc = "min device Z per texel (furthest)"},
        {.name = hzb::kClosest, .channels = {"Z"}, .doc = "max device Z per texel (closest)"}};
    io.needsCamera = true;
    io.workUnit = "texels";
    return io;
}

std::vector<Extent> HZBPass::mipExtents(Extent frame) {
    const int ex = ceilLog2(frame.width), ey = ceilLog2(frame.height);
    const int mips = std::max({ex - 1, ey - 1, 1});  // log2 of the larger mip-0 side
    return mipChain({1 << std::max(ex - 1, 0), 1 << std::max(ey - 1, 0)}, mips);
}

std::vector<Extent> HZBPass::outputExtents(std::string_view, Extent frame) const {
    return mipExtents(frame);
}

void HZBPass::execute(PassContext& ctx) {
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    hzb::run(ctx, HostPorts{ctx}, CpuPixels{}, mParams.halfPrecision,
             mipExtents({depth.width(), depth.height()}));
}

}  // namespace fp
