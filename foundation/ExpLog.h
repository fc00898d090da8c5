#pragma once
// log2, exp2 and pow of floats with the same bits on every backend, for the same reason as
// SinCos.h: libm's log2f/powf differ between C libraries and CPUs, and CUDA's are other
// algorithms again, so a pass that takes a power (Lagarde's specular occlusion, a cubemap's mip
// for a roughness) could not give the CPU's bits on the GPU. Each is evaluated in double with a
// fixed sequence of IEEE operations and rounded to float once: the argument split into a power of
// two and a mantissa in [√½, √2), the logarithm from the atanh series of (m − 1)/(m + 1) (|z| ≤
// 0.172, 12 terms, truncation below 10⁻¹⁹), the exponential from the Taylor series of 2^f on
// [−½, ½] (18 terms, below 10⁻¹⁸). The results are within 1 ulp of the correctly rounded value
// (ExpLogTests).
#include "foundation/HostDevice.h"

#include <cmath>
#include <limits>

namespace fp {

namespace explog_terms {
constexpr double kLn2 = 0.69314718055994530942;
constexpr double kInvLn2 = 1.44269504088896340736;
constexpr double kSqrtHalf = 0.70710678118654752440;
}  // namespace explog_terms

/// log2(x) in double for a finite x > 0.
FP_HD inline double log2Double(double x) {
    using namespace explog_terms;
    int e = 0;
    double m = std::frexp(x, &e);  // x = m·2^e, m ∈ [½, 1)
    if (m < kSqrtHalf) {
        m *= 2.0;
        e -= 1;
    }
    const double z = (m - 1.0) / (m + 1.0), z2 = z * z;
    // ln m = 2·(z + z³/3 + z⁵/5 + …)
    double series = 1.0 / 23.0;
    for (int k = 21; k >= 1; k -= 2) series = 1.0 / double(k) + z2 * series;
    return double(e) + 2.0 * z * series * kInvLn2;
}

/// 2^y in double for |y| < 1000 (beyond, the float result is 0 or +∞ anyway).
FP_HD inline double exp2Double(double y) {
    using namespace explog_terms;
    const double n = std::floor(y + 0.5);
    const double r = (y - n) * kLn2;  // 2^y = 2^n·e^r, |r| ≤ ln2/2
    double series = 1.0;
    for (int k = 18; k >= 1; --k) series = 1.0 + r * series / double(k);
    return std::ldexp(series, int(n));
}

/// log2(x): −∞ at 0, NaN below it and for NaN, +∞ at +∞.
FP_HD inline float log2Float(float x) {
    if (!(x > 0.0f)) return x == 0.0f ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::quiet_NaN();
    if (std::isinf(x)) return x;
    return float(log2Double(double(x)));
}

/// x^y for x ≥ 0 (NaN below 0): 1 for y = 0, 0 for x = 0 and y > 0, +∞ for x = 0 and y < 0.
FP_HD inline float powFloat(float x, float y) {
    if (y == 0.0f) return 1.0f;
    if (!(x >= 0.0f) || std::isnan(y)) return std::numeric_limits<float>::quiet_NaN();
    if (x == 0.0f) return y > 0.0f ? 0.0f : std::numeric_limits<float>::infinity();
    if (std::isinf(x)) return y > 0.0f ? x : 0.0f;
    const double t = double(y) * log2Double(double(x));
    if (t > 1000.0) return std::numeric_limits<float>::infinity();
    if (t < -1000.0) return 0.0f;
    return float(exp2Double(t));
}

}  // namespace fp
