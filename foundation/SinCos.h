#pragma once
// Sine and cosine of a float angle with the same bits on every backend. libm's sinf/cosf are a
// different algorithm per C library and per CPU (glibc picks an FMA variant at run time), and the
// GPU's another, so code that draws directions from an angle (Unreal's concentric disk, a sphere
// light's cone) could not give the scalar reference's bits in SIMD lanes or on the GPU. Here the
// angle is reduced by π/2 and both functions evaluated in double with a fixed sequence of IEEE
// operations (Taylor polynomials on [−π/4, π/4], truncation error below 3·10⁻¹⁴), then rounded to
// float once: the scalar code, the lanes (sinCos<LaneFloat>) and CUDA (-fmad=false) agree,
// and each result is within 1 ulp of the correctly rounded value (SinCosTests).
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <cmath>
#include <type_traits>

namespace fp {

namespace sincos_terms {
constexpr double kTwoOverPi = 0.63661977236758134308;
constexpr double kHalfPi = 1.57079632679489661923;
// sin r = r + r³·(S1 + r²·(S2 + …)), cos r = 1 + r²·(C1 + r²·(C2 + …)): Taylor coefficients.
constexpr double S1 = -1.0 / 6.0, S2 = 1.0 / 120.0, S3 = -1.0 / 5040.0, S4 = 1.0 / 362880.0,
                 S5 = -1.0 / 39916800.0, S6 = 1.0 / 6227020800.0;
constexpr double C1 = -1.0 / 2.0, C2 = 1.0 / 24.0, C3 = -1.0 / 720.0, C4 = 1.0 / 40320.0,
                 C5 = -1.0 / 3628800.0, C6 = 1.0 / 479001600.0, C7 = -1.0 / 87178291200.0;
}  // namespace sincos_terms

/// s = sin(angle), c = cos(angle) for |angle| ≤ 2π (accurate to 1 ulp up to about 10⁴); T: float
/// or float lanes (LaneFloat.h), evaluated in DoubleOf<T>.
template <class T>
FP_HD inline void sinCos(std::type_identity_t<T> angle, T& s, T& c) {
    using namespace sincos_terms;
    using D = DoubleOf<T>;
    const D x = toDouble(angle);
    const D q = floorOf(x * kTwoOverPi + 0.5);  // the nearest multiple of π/2
    const D r = x - q * kHalfPi;                  // |r| ≤ π/4 (plus rounding)
    const D r2 = r * r;
    const D sinR = r + r * r2 * (S1 + r2 * (S2 + r2 * (S3 + r2 * (S4 + r2 * (S5 + r2 * S6)))));
    const D cosR = 1.0 + r2 * (C1 + r2 * (C2 + r2 * (C3 + r2 * (C4 + r2 * (C5 + r2 * (C6 + r2 * C7))))));
    const D quadrant = q - 4.0 * floorOf(q * 0.25);  // 0, 1, 2 or 3, exactly
    // (Selected in this order, so a NaN angle gives the same NaN everywhere.)
    const D sinX = ifThenElse(quadrant == 1.0, cosR,
                              ifThenElse(quadrant == 2.0, -sinR, ifThenElse(quadrant == 3.0, -cosR, sinR)));
    const D cosX = ifThenElse(quadrant == 1.0, -sinR,
                              ifThenElse(quadrant == 2.0, -cosR, ifThenElse(quadrant == 3.0, sinR, cosR)));
    s = toFloat(sinX);
    c = toFloat(cosX);
}

}  // namespace fp
