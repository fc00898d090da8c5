#pragma once
// The screen-space ray march through the furthest HZB (reference §4.5–4.6, Unreal's
// CastScreenSpaceRay): samples in batches of 4, point-sampled at the nearest mip of a level that
// climbs two increments per batch, a hit where the ray is behind the cell's furthest surface by
// less than twice its tolerance. One implementation for every screen-space tracer and for both
// backends (FP_HD): SSGI calls it today, SSR will with its own tolerance and level schedule.
#include "passes/core/FloatToInt.h"
#include "passes/core/HostDevice.h"
#include "passes/core/PlaneView.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace fp {

/// Mips of an HZB a march can read: a 2¹⁶-texel-wide mip 0 is far beyond any capture.
constexpr int kMaxHzbMips = 16;

/// The furthest HZB as the march reads it (device Z, one plane per mip).
struct HzbView {
    PlaneView mips[kMaxHzbMips];
    int mipCount = 0;
};

/// The view of a host Texture or a DeviceTexture holding an HZB (at most kMaxHzbMips are read).
template <class TextureT>
HzbView hzbViewOf(const TextureT& hzb) {
    HzbView v;
    v.mipCount = hzb.mipCount() < kMaxHzbMips ? hzb.mipCount() : kMaxHzbMips;
    for (int m = 0; m < v.mipCount; ++m)
        v.mips[m] = viewOf(hzb.mip(m).plane(0));
    return v;
}

/// 2^−m exactly (m in 0…126), without a division: the march scales by it at every sample.
FP_HD inline float inversePowerOfTwo(int m) {
    return std::bit_cast<float>(uint32_t(127 - m) << 23);
}

/// Point sampling with an explicit fractional level: the nearest mip (reference §2, §13.10).
FP_HD inline int nearestMip(float level, int mipCount) {
    return floorToInt(level + 0.5f, 0, mipCount - 1);
}

/// Position in "half-resolution pixel" units: HZB mip 0 and reduced-colour mip 0 both have one
/// texel per 2×2 full-resolution pixels, so mip m texel = floor(h / 2^m) for either chain.
struct RayPoint {
    float hx, hy, z;  // half-res pixels, device Z
};

/// A ray's march, set up: sample k lies at origin + step·k.
struct RaySteps {
    RayPoint origin, step;
    float tolerance;
};

/// Furthest device Z of the cell of mip view `cells` under (hx, hy) in half-res pixels scaled
/// by `scale` = 2^−mip, clamped to the mip (the GPU's clamp addressing).
FP_HD inline float hzbCell(const PlaneView& cells, float scale, float hx, float hy) {
    return cells.at(floorToInt(hx * scale, 0, cells.width - 1),
                    floorToInt(hy * scale, 0, cells.height - 1));
}

/// Marches `steps` samples (a multiple of 4) with the level rising `levelStep` per pair of
/// samples from 1. Returns the first sample behind the furthest surface of its cell by less than
/// 2·tolerance (−1: a miss) and leaves `level` at the mip level the ray reached.
FP_HD inline int marchHzb(const HzbView& hzb,
                          const RaySteps& r,
                          int steps,
                          float levelStep,
                          float& level,
                          unsigned& hzbSamples) {
    level = 1.0f;
    int hitSample = -1;
    for (int batch = 0; batch * 4 < steps && hitSample < 0; ++batch) {
        // A batch's first two samples read the mip nearest `level`, its last two the one nearest
        // `level + levelStep`: each mip view is read once per pair.
        int mips[2] = {nearestMip(level, hzb.mipCount), nearestMip(level + levelStep, hzb.mipCount)};
        for (int pair = 0; pair < 2; ++pair) {
            const PlaneView cells = hzb.mips[mips[pair]];
            const float scale = inversePowerOfTwo(mips[pair]);
            for (int j = 0; j < 2; ++j) {
                const int k = batch * 4 + pair * 2 + j + 1;
                const float rz = r.origin.z + r.step.z * float(k);
                const float hz = hzbCell(cells, scale, r.origin.hx + r.step.hx * float(k),
                                         r.origin.hy + r.step.hy * float(k));
                const float diff = rz - hz;
                // A sky cell (device Z 0) is never hit: a ray extended past the point at
                // infinity would otherwise "hit" it [framepass guard].
                if (hitSample < 0 && hz > 0.0f && std::fabs(diff + r.tolerance) < r.tolerance)
                    hitSample = k;
            }
        }
        hzbSamples += 4;
        level += 2.0f * levelStep;
    }
    return hitSample;
}

}  // namespace fp
