#pragma once
// Float → int conversions of values that came from pixels. Converting NaN, ±inf or anything
// outside int's range is undefined behaviour in C++, so every such conversion goes through here:
// the value is clamped in floating point first and NaN goes to `lo`.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <algorithm>
#include <cmath>

namespace fp {

/// ⌊v⌋ clamped to [lo, hi]; NaN gives lo.
FP_HD inline int floorToInt(double v, int lo, int hi) {
    if (!(v >= double(lo)))
        return lo;  // NaN and −inf land here
    if (v >= double(hi))
        return hi;
    return std::clamp(int(std::floor(v)), lo, hi);
}

/// The same for a float, in float arithmetic and without a branch (GPUs convert and floor doubles
/// at a fraction of the float rate, and the HZB march does this at every sample). Clamping v to
/// the integers [lo, hi] before the floor gives the same integer as clamping after it, so this is
/// two min/max and one converting floor. Identical results while |lo| and |hi| are at most 2²⁴
/// (exact in float), which image coordinates are. floorToIntOf is the same for float lanes
/// (LaneFloat.h), `hi` then an int or each lane's own bound.
template <class T, class I>
FP_HD inline IntOf<T> floorToIntOf(T v, int lo, I hi) {
    T c = ifThenElse(v >= float(lo), v, T(float(lo)));  // NaN and −inf give lo
    const T top = toFloat(hi);
    c = ifThenElse(c <= top, c, top);
    // c lies in [lo, hi]: with lo ≥ 0 truncation is the floor (and saves a rounding a lane).
    return lo >= 0 ? toInt(c) : toInt(floorOf(c));
}
FP_HD inline int floorToInt(float v, int lo, int hi) { return floorToIntOf(v, lo, hi); }

/// v rounded towards zero and clamped to [lo, hi]; NaN gives lo.
FP_HD inline int truncToInt(double v, int lo, int hi) {
    if (!(v >= double(lo)))
        return lo;
    if (v >= double(hi))
        return hi;
    return std::clamp(int(v), lo, hi);
}

/// std::lround(v) for |v| < 2³¹ (the caller guarantees it; NaN is out of range too), without
/// libm's call: truncate, then step away from zero where the fraction is at least one half.
/// v − trunc(v) is exact in float, so the result is lround's for every such v.
FP_HD inline int roundHalfAwayToInt(float v) {
    int i = int(v);
    const float fraction = v - float(i);
    if (fraction >= 0.5f)
        ++i;
    else if (fraction <= -0.5f)
        --i;
    return i;
}

}  // namespace fp
