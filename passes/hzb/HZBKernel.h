#pragma once
// The HZB's per-texel work (algorithms §2), for HZBPass::execute and HZBPass.cu alike.
#include "screenspace/GBuffer.h"
#include "foundation/Camera.h"
#include "foundation/HalfFloat.h"
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace fp::hzb {

inline constexpr const char* kFurthest = "furthest";
inline constexpr const char* kClosest = "closest";

/// Mip-0 texel (x, y): min (furthest) and max (closest) device Z of its 2×2 full-resolution
/// pixels. Reads past the view clamp to its last pixel (InputViewportMaxBound), so texels beyond
/// W/2 repeat the edge rather than being stretched. Either output may be absent.
FP_HD inline void firstMipTexel(const CameraView& cam,
                                const PlaneView& depth,
                                const PlaneSpan& furthest,
                                const PlaneSpan& closest,
                                bool halfPrecision,
                                int x,
                                int y) {
    float lo = 1e30f, hi = -1e30f;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            const float d = depth.clampedAt(2 * x + i, 2 * y + j);
            const float z = float(cam.deviceZFromDepth(d));
            lo = std::min(lo, z);
            hi = std::max(hi, z);
        }
    if (furthest)
        furthest.at(x, y) = halfPrecision ? roundToHalf(lo) : lo;
    if (closest)
        closest.at(x, y) = halfPrecision ? roundToHalf(hi) : hi;
}

/// Texel (x, y) of a further mip: the plain 2×2 min (furthest) or max (closest) of the mip above.
FP_HD inline void reduceTexel(const PlaneView& src, const PlaneSpan& dst, bool isMin, int x, int y) {
    const float a = src.clampedAt(2 * x, 2 * y);
    const float b = src.clampedAt(2 * x + 1, 2 * y);
    const float c = src.clampedAt(2 * x, 2 * y + 1);
    const float d = src.clampedAt(2 * x + 1, 2 * y + 1);
    dst.at(x, y) = isMin ? std::min(std::min(a, b), std::min(c, d))
                         : std::max(std::max(a, b), std::max(c, d));
}

/// The whole pass on either backend (PerPixel.h): mip 0 from depth, then each further mip from
/// the one above, for the chains something reads.
template <class Ports, class Pixels>
void run(PassContext& ctx,
         const Ports& ports,
         const Pixels& pixels,
         bool halfPrecision,
         const std::vector<Extent>& extents) {
    const CameraView cam = ctx.frame().camera.current;
    const PlaneView depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    auto* furthest = ports.overwriteIfRequested(kFurthest, extents);
    auto* closest = ports.overwriteIfRequested(kClosest, extents);
    const PlaneSpan furthest0 = furthest ? spanOf(furthest->mip(0).plane(0)) : PlaneSpan{};
    const PlaneSpan closest0 = closest ? spanOf(closest->mip(0).plane(0)) : PlaneSpan{};
    pixels.template forEach<0>(
        extents[0].width, extents[0].height,
        [=] FP_HD(int x, int y, WorkCounts<0>&) {
            firstMipTexel(cam, depth, furthest0, closest0, halfPrecision, x, y);
        },
        "hzb");
    for (int m = 1; m < int(extents.size()); ++m)
        for (auto* chain : {furthest, closest}) {
            if (!chain)
                continue;
            const bool isMin = chain == furthest;
            const PlaneView src = viewOf(chain->mip(m - 1).plane(0));
            const PlaneSpan dst = spanOf(chain->mip(m).plane(0));
            pixels.template forEach<0>(
                extents[m].width, extents[m].height,
                [=] FP_HD(int x, int y, WorkCounts<0>&) { reduceTexel(src, dst, isMin, x, y); },
                "hzb");
        }
    uint64_t texels = 0;
    for (const Extent& e : extents)
        texels += uint64_t(e.width) * e.height;
    ctx.addWork("texels", texels * (uint64_t(furthest != nullptr) + uint64_t(closest != nullptr)));
}

}  // namespace fp::hzb
