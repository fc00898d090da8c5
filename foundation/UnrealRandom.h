#pragma once
// Unreal's own per-pixel random sequences (algorithms §1.9), reproduced so that a pass that mirrors
// an Unreal shader draws the same numbers for the same pixel and frame index: interleaved gradient
// noise, the 16-bit PCG hash of (x, y, frame) and the scrambled Hammersley point set.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/SinCos.h"

#include <cmath>
#include <cstdint>

namespace fp::ue {

/// View.StateFrameIndexMod8 of an absolute frame number (also for negative frames).
FP_HD inline uint32_t frameIndexMod8(int64_t frame) { return uint32_t(((frame % 8) + 8) % 8); }

/// Interleaved gradient noise at pixel position (x, y) (usually pixel + 0.5) for frame index
/// `frameMod8` (View.StateFrameIndexMod8).
FP_HD inline float interleavedGradientNoise(float x, float y, uint32_t frameMod8) {
    x += float(frameMod8) * 47.0f * 0.695f;
    y += float(frameMod8) * 17.0f * 0.695f;
    const float inner = 0.06711056f * x + 0.00583715f * y;
    const float f = 52.9829189f * (inner - std::floor(inner));
    return f - std::floor(f);
}

struct Rand3 {
    uint32_t x, y, z;  //!< 16-bit values
};

/// Rand3DPCG16: an LCG step on each component, two rounds of the three-way mix, top 16 bits.
FP_HD constexpr Rand3 rand3DPCG16(int32_t px, int32_t py, int32_t pz) {
    uint32_t x = uint32_t(px) * 1664525u + 1013904223u;
    uint32_t y = uint32_t(py) * 1664525u + 1013904223u;
    uint32_t z = uint32_t(pz) * 1664525u + 1013904223u;
    for (int round = 0; round < 2; ++round) {
        x += y * z;
        y += z * x;
        z += x * y;
    }
    return {x >> 16u, y >> 16u, z >> 16u};
}

/// The 32 bits of v in reverse order; U: uint32_t or unsigned lanes (LaneFloat.h).
template <class U>
FP_HD constexpr U reverseBits32(U v) {
    v = ((v >> 1u) & 0x55555555u) | ((v & 0x55555555u) << 1u);
    v = ((v >> 2u) & 0x33333333u) | ((v & 0x33333333u) << 2u);
    v = ((v >> 4u) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4u);
    v = ((v >> 8u) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8u);
    return (v >> 16u) | (v << 16u);
}

/// Point `index` of `count` of the Hammersley set, scrambled by a 16-bit seed pair:
/// E1 = frac(i/N + seed.x/65536), E2 = ((reverse(i) >> 16) xor seed.y)/65536. T: float, or float
/// lanes with `index` in UIntOf<T> (a point a lane).
template <class T>
FP_HD inline void hammersley16(UIntOf<T> index, uint32_t count, uint32_t seedX, uint32_t seedY, T& e1,
                               T& e2) {
    const T a = toFloat(index) / float(count) + float(seedX & 0xFFFFu) * (1.0f / 65536.0f);
    e1 = a - floorOf(a);
    e2 = toFloat(((reverseBits32(index) >> 16u) ^ seedY) & 0xFFFFu) * (1.0f / 65536.0f);
}

/// Unreal's concentric disk mapping (algorithms §1.9): the angle is built in the first quadrant
/// from Lo/Hi and the signs of the input are copied onto the result.
template <class T>
FP_HD inline void concentricDisk(T e1, T e2, T& x, T& y) {
    const T px = 2.0f * e1 - 1.0f, py = 2.0f * e2 - 1.0f;
    const T ax = absOf(px), ay = absOf(py);
    const auto xBelowY = ax < ay;
    const T lo = ifThenElse(xBelowY, ax, ay), hi = ifThenElse(xBelowY, ay, ax);
    const T phi = 0.78539816f * (lo / (hi + 5.42101086243e-20f) + ifThenElse(ay >= ax, T(2.0f), T(0.0f)));
    T sinPhi, cosPhi;
    sinCos(phi, sinPhi, cosPhi);  // the same bits on the CPU, in SIMD lanes and on the GPU
    x = copySignOf(absOf(cosPhi) * hi, px);
    y = copySignOf(absOf(sinPhi) * hi, py);
}

/// Unreal's luminance weights (Common.ush Luminance), used by Karis weighting.
template <class T>
FP_HD inline T luma(T r, T g, T b) { return 0.3f * r + 0.59f * g + 0.11f * b; }

}  // namespace fp::ue
