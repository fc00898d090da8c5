// The scalar reference's comparisons in SIMD lanes (Google Highway), for the passes that run their
// per-pixel arithmetic a vector at a time and must give the scalar code's bits. Highway's Min, Max
// and Clamp decide NaN the way the x86 instructions do; these decide it as std::min, std::max and
// std::clamp do, so a NaN input leaves the same NaN or bound in a lane as in the scalar code.
//
// A per-target header: include it after <hwy/highway.h> from a file that foreach_target.h
// compiles once per instruction set (the guard below toggles with HWY_TARGET_TOGGLE).
#if defined(FP_PASSES_COMMON_LANE_MATH_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef FP_PASSES_COMMON_LANE_MATH_H_
#undef FP_PASSES_COMMON_LANE_MATH_H_
#else
#define FP_PASSES_COMMON_LANE_MATH_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fp::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

/// std::min(a, b): (b < a) ? b : a.
template <class V>
HWY_INLINE V minLike(V a, V b) {
    return hn::IfThenElse(b < a, b, a);
}

/// std::max(a, b): (a < b) ? b : a.
template <class V>
HWY_INLINE V maxLike(V a, V b) {
    return hn::IfThenElse(a < b, b, a);
}

/// std::clamp(v, lo, hi): (v < lo) ? lo : (hi < v) ? hi : v.
template <class V>
HWY_INLINE V clampLike(V v, V lo, V hi) {
    return hn::IfThenElse(v < lo, lo, hn::IfThenElse(hi < v, hi, v));
}

}  // namespace fp::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
