#pragma once
// display's per-pixel maths for both backends. The exposure, the NaN guard, the channel mapping
// and the clamp are the same code on the CPU and the GPU. The colour transform is OpenColorIO's
// CPU processor on the CPU; OCIO has no CUDA path, so the GPU applies the same processor baked,
// per channel, into a table over every half-float value and interpolated linearly between
// neighbouring halves (a relative step of 2⁻¹⁰). That is possible only for a transform without
// channel crosstalk (the shipped sRGB view is one); a view that mixes channels runs on the CPU.
#include "color/FilmicTonemap.h"
#include "foundation/HostDevice.h"
#include "foundation/PlaneView.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace fp::display {

/// The table has one entry per half bit pattern: index = sign (0x8000) | magnitude bits.
inline constexpr int kHalfLutSize = 65536;
inline constexpr uint32_t kMaxFiniteHalf = 0x7BFF;  // 65504

/// Exposure, then no NaN or infinity reaches a preview.
FP_HD inline float exposed(float v, float gain) {
    const float e = v * gain;
    return std::isfinite(e) ? e : 0.0f;
}

/// The source channel of preview channel `c` (0–2) of a `channels`-channel buffer: 1 channel
/// shows as grey; 2 channels as R, G and a black B (−1: no source).
FP_HD inline int previewSource(int c, int channels) {
    const int from = channels == 1 ? 0 : c;
    return from < channels ? from : -1;
}

/// Magnitude bits of the largest half not above `a` (finite, ≥ 0); 65504 and above give 65504.
FP_HD inline uint32_t halfBitsBelow(float a) {
    if (a >= 65504.0f)
        return kMaxFiniteHalf;
    if (a < 6.103515625e-05f)                     // subnormal halves: steps of 2⁻²⁴
        return uint32_t(a * 16777216.0f);         // exact scaling, truncated
    const uint32_t bits = std::bit_cast<uint32_t>(a);
    const uint32_t exponent = (bits >> 23) - 127u + 15u;  // 1 … 30
    return (exponent << 10) | ((bits >> 13) & 0x3FFu);
}

/// The value of half magnitude bits `h` (no sign, finite).
FP_HD inline float halfValue(uint32_t h) {
    const uint32_t exponent = h >> 10, mantissa = h & 0x3FFu;
    if (exponent == 0)
        return float(mantissa) * 5.9604644775390625e-08f;  // m · 2⁻²⁴, exact
    return std::bit_cast<float>(((exponent - 15u + 127u) << 23) | (mantissa << 13));
}

/// One channel of the baked transform at `v`: linear between the two halves around |v| on v's
/// side of zero; beyond ±65504 the value at ±65504.
FP_HD inline float halfLutLookup(const PlaneView& lut, float v) {
    const float a = std::fabs(v);
    const uint32_t h = halfBitsBelow(a);
    const int index = int((std::signbit(v) ? 0x8000u : 0u) | h);
    const float lo = lut.at(index, 0);
    if (h >= kMaxFiniteHalf)
        return lo;
    const float x0 = halfValue(h), x1 = halfValue(h + 1);
    const float t = (a - x0) / (x1 - x0);
    return lo + t * (lut.at(index + 1, 0) - lo);
}

/// What one pixel of the preview reads and writes.
struct Frame {
    PlaneView src[4];
    int channels;
    float gain;
    PlaneView lut[3];  // null for a data buffer or the film curve: no table
    bool film = false;  // Unreal's filmic tonemapper and the sRGB encoding instead of a table
    color::FilmParams filmParams;
    PlaneSpan dst[3];
};

/// The preview pixel (x, y).
FP_HD inline void displayPixel(const Frame& f, int x, int y) {
    float v[3];
    for (int c = 0; c < 3; ++c) {
        const int from = previewSource(c, f.channels);
        v[c] = from >= 0 ? exposed(f.src[from].at(x, y), f.gain) : 0.0f;
    }
    if (f.film) {
        float toned[3];
        color::ue4FilmicTonemap(f.filmParams, v, toned);
        for (int c = 0; c < 3; ++c) v[c] = color::srgbEncode(toned[c] > 1.0f ? 1.0f : toned[c]);
    }
    for (int c = 0; c < 3; ++c) {
        if (f.lut[c].data)
            v[c] = halfLutLookup(f.lut[c], v[c]);
        f.dst[c].at(x, y) = v[c] < 0.0f ? 0.0f : (v[c] > 1.0f ? 1.0f : v[c]);
    }
}

}  // namespace fp::display
