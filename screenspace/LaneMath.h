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

#include "foundation/SinCos.h"

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

/// Three components in lanes (Vec3f's fields a vector at a time), combined as Vec3f's operators
/// combine them.
template <class V>
struct Vec3Lanes {
    V x, y, z;
};

/// Three planes' lanes from `x`, `y`, `z` (unaligned).
template <class D>
HWY_INLINE Vec3Lanes<hn::Vec<D>> load3(D d, const float* x, const float* y, const float* z) {
    return {hn::LoadU(d, x), hn::LoadU(d, y), hn::LoadU(d, z)};
}

/// dot(a, b) = a.x·b.x + a.y·b.y + a.z·b.z, left to right.
template <class V>
HWY_INLINE V dot3(const Vec3Lanes<V>& a, const Vec3Lanes<V>& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/// normalize(a): a / length(a) where the length is positive, else the zero vector.
template <class V>
HWY_INLINE Vec3Lanes<V> normalize3(const Vec3Lanes<V>& a) {
    const V l = hn::Sqrt(dot3(a, a));
    const auto positive = l > hn::Zero(hn::DFromV<V>());
    return {hn::IfThenElseZero(positive, a.x / l), hn::IfThenElseZero(positive, a.y / l),
            hn::IfThenElseZero(positive, a.z / l)};
}

/// fp::sinCos (SinCos.h) of the float lanes of `angle` (D: a float tag), the same operations on
/// double lanes, so the same bits.
template <class D>
HWY_INLINE void sinCosLanes(D d, hn::Vec<D> angle, hn::Vec<D>& s, hn::Vec<D>& c) {
#if HWY_TARGET == HWY_SCALAR  // one lane: no halves to promote
    float sv, cv;
    fp::sinCos(hn::GetLane(angle), sv, cv);
    s = hn::Set(d, sv);
    c = hn::Set(d, cv);
#else
    using namespace fp::sincos_terms;
    const hn::Half<D> dh;
    const hn::Rebind<double, hn::Half<D>> dd;
    using VD = hn::Vec<decltype(dd)>;
    const auto half = [&](hn::Vec<decltype(dh)> a, hn::Vec<decltype(dh)>& sh,
                          hn::Vec<decltype(dh)>& ch) {
        const VD x = hn::PromoteTo(dd, a);
        const VD q = hn::Floor(x * hn::Set(dd, kTwoOverPi) + hn::Set(dd, 0.5));
        const VD r = x - q * hn::Set(dd, kHalfPi);
        const VD r2 = r * r;
        const auto k = [&](double v) { return hn::Set(dd, v); };
        const VD sinR = r + r * r2 * (k(S1) + r2 * (k(S2) + r2 * (k(S3) + r2 * (k(S4) +
                                      r2 * (k(S5) + r2 * k(S6))))));
        const VD cosR = k(1.0) + r2 * (k(C1) + r2 * (k(C2) + r2 * (k(C3) + r2 * (k(C4) +
                                       r2 * (k(C5) + r2 * (k(C6) + r2 * k(C7)))))));
        const VD quadrant = q - k(4.0) * hn::Floor(q * k(0.25));
        const auto q1 = quadrant == k(1.0), q2 = quadrant == k(2.0), q3 = quadrant == k(3.0);
        const VD sinX = hn::IfThenElse(q1, cosR, hn::IfThenElse(q2, hn::Neg(sinR),
                                       hn::IfThenElse(q3, hn::Neg(cosR), sinR)));
        const VD cosX = hn::IfThenElse(q1, hn::Neg(sinR), hn::IfThenElse(q2, hn::Neg(cosR),
                                       hn::IfThenElse(q3, sinR, cosR)));
        sh = hn::DemoteTo(dh, sinX);
        ch = hn::DemoteTo(dh, cosX);
    };
    hn::Vec<decltype(dh)> sLo, cLo, sHi, cHi;
    half(hn::LowerHalf(dh, angle), sLo, cLo);
    half(hn::UpperHalf(dh, angle), sHi, cHi);
    s = hn::Combine(d, sHi, sLo);
    c = hn::Combine(d, cHi, cLo);
#endif
}

/// ue::concentricDisk (UnrealRandom.h) of the lanes (e1, e2): the angle built in the first
/// quadrant from Lo/Hi, its sine and cosine from sinCosLanes, the inputs' signs copied on.
template <class D>
HWY_INLINE void concentricDiskLanes(D d, hn::Vec<D> e1, hn::Vec<D> e2, hn::Vec<D>& x,
                                    hn::Vec<D>& y) {
    using V = hn::Vec<D>;
    const V one = hn::Set(d, 1.0f), two = hn::Set(d, 2.0f);
    const V px = two * e1 - one, py = two * e2 - one;
    const V ax = hn::Abs(px), ay = hn::Abs(py);
    const auto xBelowY = ax < ay;
    const V lo = hn::IfThenElse(xBelowY, ax, ay), hi = hn::IfThenElse(xBelowY, ay, ax);
    const V quadrant = hn::IfThenElseZero(ay >= ax, two);
    const V phi =
        hn::Set(d, 0.78539816f) * (lo / (hi + hn::Set(d, 5.42101086243e-20f)) + quadrant);
    V sinPhi, cosPhi;
    sinCosLanes(d, phi, sinPhi, cosPhi);
    x = hn::CopySign(hn::Abs(cosPhi) * hi, px);
    y = hn::CopySign(hn::Abs(sinPhi) * hi, py);
}

}  // namespace fp::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
