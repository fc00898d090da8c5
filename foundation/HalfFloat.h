#pragma once
// Rounding to IEEE half precision, for passes that mirror a PF_R16F render target (the HZB,
// algorithms §2) so their texels carry the same quantisation as Unreal's.
#include "foundation/HostDevice.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace fp {

/// The float nearest to `v` that a half can hold (round to nearest even; overflow → ±inf).
FP_HD inline float roundToHalf(float v) {
    if (!std::isfinite(v) || v == 0.0f) return v;
    const uint32_t bits = std::bit_cast<uint32_t>(v);
    const uint32_t sign = bits & 0x80000000u;
    const float a = std::fabs(v);
    if (a >= 65520.0f) return std::bit_cast<float>(sign | 0x7F800000u);
    // Below 2^-14 halves are subnormal with a fixed step of 2^-24.
    const int exponent = a < 6.103515625e-05f ? -14 : std::ilogb(a);
    const float step = std::ldexp(1.0f, exponent - 10);
    const float q = std::nearbyint(a / step) * step;  // default rounding mode: ties to even
    return std::bit_cast<float>(sign | std::bit_cast<uint32_t>(q));
}

}  // namespace fp
