#include "passes/hzb/HZBPass.h"

#include "passes/common/GBuffer.h"
#include "passes/core/HalfFloat.h"
#include "passes/core/Tiles.h"

#include <algorithm>
#include <bit>

namespace fp {

namespace {
constexpr const char* kFurthest = "furthest";
constexpr const char* kClosest = "closest";

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
        {.name = kFurthest, .channels = {"Z"}, .doc = "min device Z per texel (furthest)"},
        {.name = kClosest, .channels = {"Z"}, .doc = "max device Z per texel (closest)"}};
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
    const CameraView& cam = ctx.frame().camera.current;
    const Extent frame{depth.width(), depth.height()};
    const auto extents = mipExtents(frame);
    const bool wantFurthest = ctx.isRequested(kFurthest);
    const bool wantClosest = ctx.isRequested(kClosest);
    Texture* furthest = wantFurthest ? &ctx.output(kFurthest, extents) : nullptr;
    Texture* closest = wantClosest ? &ctx.output(kClosest, extents) : nullptr;
    const bool half = mParams.halfPrecision;
    auto store = [half](float v) { return half ? roundToHalf(v) : v; };

    // Mip 0: 2×2 full-resolution pixels per texel; reads past the view clamp to its last pixel
    // (InputViewportMaxBound), so texels beyond W/2 repeat the edge rather than being stretched.
    const Extent e0 = extents[0];
    forEachTile(e0.width, e0.height, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y) {
            float* fRow = furthest ? furthest->mip(0).plane(0).row(y) : nullptr;
            float* cRow = closest ? closest->mip(0).plane(0).row(y) : nullptr;
            for (int x = t.x0; x < t.x1; ++x) {
                float lo = 1e30f, hi = -1e30f;
                for (int j = 0; j < 2; ++j)
                    for (int i = 0; i < 2; ++i) {
                        const float d = depth.clampedAt(2 * x + i, 2 * y + j);
                        const float z = float(cam.deviceZFromDepth(d));
                        lo = std::min(lo, z);
                        hi = std::max(hi, z);
                    }
                if (fRow)
                    fRow[x] = store(lo);
                if (cRow)
                    cRow[x] = store(hi);
            }
        }
    });
    // Further mips: plain 2×2 min / max of the level above.
    for (int m = 1; m < int(extents.size()); ++m) {
        for (Texture* tex : {furthest, closest}) {
            if (!tex)
                continue;
            const bool isMin = tex == furthest;
            const Plane& src = tex->mip(m - 1).plane(0);
            Plane& dst = tex->mip(m).plane(0);
            forEachTile(dst.width(), dst.height(), [&](const Tile& t) {
                for (int y = t.y0; y < t.y1; ++y)
                    for (int x = t.x0; x < t.x1; ++x) {
                        const float a = src.clampedAt(2 * x, 2 * y);
                        const float b = src.clampedAt(2 * x + 1, 2 * y);
                        const float c = src.clampedAt(2 * x, 2 * y + 1);
                        const float d = src.clampedAt(2 * x + 1, 2 * y + 1);
                        dst.at(x, y) = isMin ? std::min(std::min(a, b), std::min(c, d))
                                             : std::max(std::max(a, b), std::max(c, d));
                    }
            });
        }
    }
    uint64_t texels = 0;
    for (const Extent& e : extents)
        texels += uint64_t(e.width) * e.height;
    ctx.addWork("texels", texels * (uint64_t(wantFurthest) + uint64_t(wantClosest)));
}

}  // namespace fp
