#pragma once
// The number types that let a kernel be written once for one pixel (or ray) and for a SIMD vector
// of them. A kernel templated on its number type T runs with T = float for one (the CPU's scalar
// reference and the CUDA thread) and with T = LaneFloat<N> for N at once on the CPU. Its
// comparisons give a mask (bool for float, LaneMask<N> here), which it combines with ifThenElse,
// anyLane, countLanes, minLike, maxLike and saturate instead of `?:`, `if` or std::min/max; its
// integers are IntOf<T> / UIntOf<T> and its doubles DoubleOf<T> (int, uint32_t and double for
// float; LaneInt, LaneUInt and LaneDouble of N lanes here), converted with toFloat, toDouble and
// toInt; a lane reads memory at its own index with gatherAt. Math.h gives
// every one of these names for float; the definitions below give them for lanes.
//
// The lane types are GCC vectors (vector_size): the compiler lowers their operators to the
// instructions of the function they end up in. A per-instruction-set function (Highway's
// foreach_target.h compiles one per x86 target) that is __attribute__((flatten)) inlines the whole
// templated kernel, so the kernel becomes SSE4, AVX2 or AVX-512 code there. Every operation is the
// IEEE operation the scalar code does, lane by lane, in the same order (no contraction: the build
// sets -ffp-contract=off), so each lane gives the scalar code's bits. sqrtOf and floorOf are loops
// of __builtin_sqrtf / __builtin_floorf that the vectoriser turns into one vector instruction when
// the file is built with -fno-math-errno (the results are the same correctly rounded values).
//
// Host only: the CUDA kernels instantiate the same templates with float.
#include "foundation/Math.h"
#include "foundation/PlaneView.h"

#include <cstdint>
#include <cstring>
#if defined(__x86_64__)
#include <immintrin.h>  // declares the gather builtins gatherAt uses
#endif
#include <limits>
#include <type_traits>
#include <utility>

#if defined(__CUDACC__)
#error "LaneFloat.h is the CPU's lane type; CUDA kernels run the templates with float"
#endif

namespace fp {

/// The floats a vector of a per-target build holds, from Highway's HWY_LANES(float) there: 16
/// with AVX-512, 8 with AVX2, 4 with SSE4, and 4 for Highway's scalar fallback too (its build
/// runs 4-wide GCC vectors on the baseline SSE2). Every lanes file takes its LaneFloat's width
/// from here.
constexpr int lanesForTarget(int hwyLanes) {
    return hwyLanes < 4 ? 4 : hwyLanes;
}

template <int N>
struct LaneVectors;  // GCC vector types of N lanes (vector_size takes no template value)
template <>
struct LaneVectors<4> {
    typedef float F __attribute__((vector_size(16)));
    typedef int I __attribute__((vector_size(16)));
    typedef uint32_t U __attribute__((vector_size(16)));
    typedef float FH __attribute__((vector_size(8)));  // half the lanes
    typedef double DH __attribute__((vector_size(16)));
    typedef long long LH __attribute__((vector_size(16)));
};
template <>
struct LaneVectors<8> {
    typedef float F __attribute__((vector_size(32)));
    typedef int I __attribute__((vector_size(32)));
    typedef uint32_t U __attribute__((vector_size(32)));
    typedef float FH __attribute__((vector_size(16)));  // half the lanes
    typedef double DH __attribute__((vector_size(32)));
    typedef long long LH __attribute__((vector_size(32)));
};
template <>
struct LaneVectors<16> {
    typedef float F __attribute__((vector_size(64)));
    typedef int I __attribute__((vector_size(64)));
    typedef uint32_t U __attribute__((vector_size(64)));
    typedef float FH __attribute__((vector_size(32)));  // half the lanes
    typedef double DH __attribute__((vector_size(64)));
    typedef long long LH __attribute__((vector_size(64)));
};

#define FP_LANE_OP __attribute__((always_inline)) inline

namespace lanes_detail {
/// The lanes I… of a and b (a's lanes first), one shuffle.
template <class V, std::size_t... I>
FP_LANE_OP auto pick(V a, V b, std::index_sequence<I...>) { return __builtin_shufflevector(a, b, I...); }
template <std::size_t Offset, std::size_t... I>
constexpr std::index_sequence<(Offset + I)...> shifted(std::index_sequence<I...>) { return {}; }
template <std::size_t... I>
constexpr std::index_sequence<(I * 0)...> zeros(std::index_sequence<I...>) { return {}; }
/// Every lane of a V of N lanes `x`: lane 0 shuffled into all, which GCC and clang make one
/// broadcast instruction (x − V{} became a chain of inserts in a large function).
template <class V, int N, class E>
FP_LANE_OP V broadcast(E x) {
    V first{};
    first[0] = x;
    return pick(first, first, zeros(std::make_index_sequence<N>{}));
}

// A vector comparison's mask type is fixed when GCC parses the function that holds it, from that
// function's instruction set: lanes of all-ones bits below AVX-512, mask registers for 512-bit
// vectors with AVX-512. A 512-bit comparison or select parsed in a default-target helper and
// inlined into an AVX-512 function keeps the former, which AVX-512 has no instruction for, so GCC
// 12 compares lane by lane (4.5× slower SSGI). So every comparison and select of the lane types
// goes through compared/selected below, and their 512-bit versions carry AVX-512's target: plain
// inline, not always_inline (GCC refuses to force a function of a wider target into the kernel
// templates, which have the default one); the flatten of the AVX-512 function that runs a kernel
// inlines them there.
//
// With GCC the 512-bit outcome is kept as AVX-512 keeps it, one bit a lane (a mask register):
// a comparison is the AVX-512 compare into a mask register and a select the masked blend. Held
// as a vector of all-ones lanes instead, each outcome went from the mask register into a vector
// and back before each select (two instructions more on the march's critical path: SSGI's
// AVX-512 lanes 15 % slower than Highway's, which keeps its masks in mask registers).
enum class Compare { less, lessEqual, equal, notEqual };
#if defined(__x86_64__) && !defined(__clang__)
inline constexpr bool kBitMasks = true;
#else
inline constexpr bool kBitMasks = false;
#endif
/// Whether comparisons of vector V give a bit a lane (else a vector of all-ones lanes).
template <class V>
inline constexpr bool kBitMaskOf = kBitMasks && sizeof(V) == 64;

#if defined(__clang__)  // clang picks mask types when it generates code (the fuzz build): as any other
#define FP_WIDE_LANE_OP FP_LANE_OP
#else
#define FP_WIDE_LANE_OP __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw"))) inline
#endif
template <Compare C, class V, std::enable_if_t<!kBitMaskOf<V>, int> = 0>
FP_LANE_OP auto compared(V a, V b) {
    if constexpr (C == Compare::less) return a < b;
    else if constexpr (C == Compare::lessEqual) return a <= b;
    else if constexpr (C == Compare::equal) return a == b;
    else return a != b;
}
template <class M, class V, std::enable_if_t<!kBitMaskOf<V>, int> = 0>
FP_LANE_OP V selected(M m, V a, V b) { return m ? a : b; }

#if defined(__x86_64__) && !defined(__clang__)
/// The comparison's outcome a bit a lane: AVX-512's compare of floats, doubles, ints or unsigned
/// ints with C's predicate (the float ones ordered and signalling, as C's <, <= and ==; != true
/// where either side is NaN).
template <Compare C, class V, std::enable_if_t<kBitMaskOf<V>, int> = 0>
FP_WIDE_LANE_OP auto compared(V a, V b) {
    using E = std::remove_cv_t<std::remove_reference_t<decltype(a[0])>>;
    typedef int I16 __attribute__((vector_size(64)));
    typedef long long I8 __attribute__((vector_size(64)));
    // The predicates: _CMP_LT_OS, _CMP_LE_OS, _CMP_EQ_OQ, _CMP_NEQ_UQ for reals, and for integers
    // _MM_CMPINT_LT, _LE, _EQ, _NE, which have the same numbers.
    constexpr int predicate = C == Compare::less ? 1 : C == Compare::lessEqual ? 2 : C == Compare::equal ? 0 : 4;
    if constexpr (std::is_same_v<E, float>)
        return (unsigned short)__builtin_ia32_cmpps512_mask(a, b, predicate, (unsigned short)0xFFFF, 4);
    else if constexpr (std::is_same_v<E, double>)
        return (unsigned char)__builtin_ia32_cmppd512_mask(a, b, predicate, (unsigned char)0xFF, 4);
    else if constexpr (sizeof(E) == 4 && std::is_signed_v<E>)
        return (unsigned short)__builtin_ia32_cmpd512_mask((I16)a, (I16)b, predicate, (unsigned short)0xFFFF);
    else if constexpr (sizeof(E) == 4)
        return (unsigned short)__builtin_ia32_ucmpd512_mask((I16)a, (I16)b, predicate, (unsigned short)0xFFFF);
    else
        return (unsigned char)__builtin_ia32_cmpq512_mask((I8)a, (I8)b, predicate, (unsigned char)0xFF);
}
/// m ? a : b, lane by lane, for an outcome a bit a lane: AVX-512's masked blend.
template <class M, class V, std::enable_if_t<kBitMaskOf<V>, int> = 0>
FP_WIDE_LANE_OP V selected(M m, V a, V b) {
    using E = std::remove_cv_t<std::remove_reference_t<decltype(a[0])>>;
    typedef int I16 __attribute__((vector_size(64)));
    typedef long long I8 __attribute__((vector_size(64)));
    if constexpr (std::is_same_v<E, float>)
        return __builtin_ia32_blendmps_512_mask(b, a, m);
    else if constexpr (std::is_same_v<E, double>)
        return __builtin_ia32_blendmpd_512_mask(b, a, m);
    else if constexpr (sizeof(E) == 4)
        return (V)__builtin_ia32_blendmd_512_mask((I16)b, (I16)a, m);
    else
        return (V)__builtin_ia32_blendmq_512_mask((I8)b, (I8)a, m);
}
#endif
#undef FP_WIDE_LANE_OP
}  // namespace lanes_detail

/// N comparisons' outcomes, V a GCC vector of N integers as wide as the compared lanes: all bits
/// set in a lane where true (GCC's vector comparison result), or with AVX-512's 512-bit vectors a
/// bit a lane (lanes_detail::kBitMaskOf).
template <class V, int N, bool Bits = lanes_detail::kBitMaskOf<V>>
struct LaneMaskOf {
    V v;

    friend FP_LANE_OP LaneMaskOf operator!(LaneMaskOf a) {
        return {(V)lanes_detail::compared<lanes_detail::Compare::equal>(a.v, V{})};  // long → long long
    }
    friend FP_LANE_OP LaneMaskOf operator|(LaneMaskOf a, LaneMaskOf b) { return {a.v | b.v}; }
    friend FP_LANE_OP LaneMaskOf operator&(LaneMaskOf a, LaneMaskOf b) { return {a.v & b.v}; }
    friend FP_LANE_OP bool anyLane(LaneMaskOf a) {
        unsigned long long words[sizeof(V) / 8];
        std::memcpy(words, &a.v, sizeof words);
        unsigned long long any = 0;
        for (unsigned long long w : words) any |= w;
        return any != 0;
    }
    /// How many lanes are true.
    friend FP_LANE_OP int countLanes(LaneMaskOf a) {
        int n = 0;
        for (int i = 0; i < N; ++i) n += a.v[i] != 0;
        return n;
    }
    friend FP_LANE_OP bool laneOf(LaneMaskOf a, int i) { return a.v[i] != 0; }
    /// Lane i's outcome (0 or 1) into out[i].
    FP_LANE_OP void store(bool* out) const {
        for (int i = 0; i < N; ++i) out[i] = v[i] != 0;
    }
};
/// The same, a bit a lane (bit i: lane i).
template <class V, int N>
struct LaneMaskOf<V, N, true> {
    using Word = std::conditional_t<(N > 8), unsigned short, unsigned char>;
    Word v;

    friend FP_LANE_OP LaneMaskOf operator!(LaneMaskOf a) { return {Word(~a.v)}; }
    friend FP_LANE_OP LaneMaskOf operator|(LaneMaskOf a, LaneMaskOf b) { return {Word(a.v | b.v)}; }
    friend FP_LANE_OP LaneMaskOf operator&(LaneMaskOf a, LaneMaskOf b) { return {Word(a.v & b.v)}; }
    friend FP_LANE_OP bool anyLane(LaneMaskOf a) { return a.v != 0; }
    friend FP_LANE_OP int countLanes(LaneMaskOf a) { return __builtin_popcount(unsigned(a.v)); }
    friend FP_LANE_OP bool laneOf(LaneMaskOf a, int i) { return (a.v >> i) & 1u; }
    FP_LANE_OP void store(bool* out) const {
        for (int i = 0; i < N; ++i) out[i] = (v >> i) & 1u;
    }
};
template <int N>
using LaneMask = LaneMaskOf<typename LaneVectors<N>::I, N>;

/// N integers (E: int or uint32_t), one a lane; every operator is E's lane by lane (uint32_t's
/// shifts are logical, int's arithmetic).
template <class V, class E, int N>
struct LaneIntegers {
    V v;

    LaneIntegers() = default;
    FP_LANE_OP constexpr LaneIntegers(V x) : v(x) {}
    /// Every lane `x` (lanes_detail::broadcast).
    FP_LANE_OP LaneIntegers(E x) : v(lanes_detail::broadcast<V, N>(x)) {}

    /// N values from `p` (unaligned) and back.
    static FP_LANE_OP LaneIntegers load(const E* p) {
        LaneIntegers r;
        std::memcpy(&r.v, p, sizeof r.v);
        return r;
    }
    FP_LANE_OP void store(E* p) const { std::memcpy(p, &v, sizeof v); }

    friend FP_LANE_OP LaneIntegers operator+(LaneIntegers a, LaneIntegers b) { return a.v + b.v; }
    friend FP_LANE_OP LaneIntegers operator-(LaneIntegers a, LaneIntegers b) { return a.v - b.v; }
    friend FP_LANE_OP LaneIntegers operator*(LaneIntegers a, LaneIntegers b) { return a.v * b.v; }
    friend FP_LANE_OP LaneIntegers operator&(LaneIntegers a, LaneIntegers b) { return a.v & b.v; }
    friend FP_LANE_OP LaneIntegers operator|(LaneIntegers a, LaneIntegers b) { return a.v | b.v; }
    friend FP_LANE_OP LaneIntegers operator^(LaneIntegers a, LaneIntegers b) { return a.v ^ b.v; }
    friend FP_LANE_OP LaneIntegers operator<<(LaneIntegers a, E bits) { return a.v << bits; }
    friend FP_LANE_OP LaneIntegers operator>>(LaneIntegers a, E bits) { return a.v >> bits; }
    /// Each lane shifted by its own amount (0 to 31).
    friend FP_LANE_OP LaneIntegers operator>>(LaneIntegers a, LaneIntegers bits) { return a.v >> bits.v; }
    friend FP_LANE_OP LaneMask<N> operator<(LaneIntegers a, LaneIntegers b) {
        return {lanes_detail::compared<lanes_detail::Compare::less>(a.v, b.v)};
    }
    friend FP_LANE_OP LaneMask<N> operator==(LaneIntegers a, LaneIntegers b) {
        return {lanes_detail::compared<lanes_detail::Compare::equal>(a.v, b.v)};
    }
    friend FP_LANE_OP E laneOf(LaneIntegers a, int i) { return a.v[i]; }
};
template <int N>
using LaneInt = LaneIntegers<typename LaneVectors<N>::I, int, N>;
template <int N>
using LaneUInt = LaneIntegers<typename LaneVectors<N>::U, uint32_t, N>;

/// N reals (E: float or double), one a lane; every operator is E's lane by lane. `Mask` is the
/// outcome of their comparisons.
template <class V, class E, class Mask, int N>
struct LaneReals {
    V v;

    LaneReals() = default;
    FP_LANE_OP constexpr LaneReals(V x) : v(x) {}
    /// Every lane `x`, −0 and NaN as they are (lanes_detail::broadcast).
    FP_LANE_OP LaneReals(E x) : v(lanes_detail::broadcast<V, N>(x)) {}

    /// N values from `p` (unaligned) and back.
    static FP_LANE_OP LaneReals load(const E* p) {
        LaneReals r;
        std::memcpy(&r.v, p, sizeof r.v);
        return r;
    }
    FP_LANE_OP void store(E* p) const { std::memcpy(p, &v, sizeof v); }

    friend FP_LANE_OP LaneReals operator+(LaneReals a, LaneReals b) { return a.v + b.v; }
    friend FP_LANE_OP LaneReals operator-(LaneReals a, LaneReals b) { return a.v - b.v; }
    friend FP_LANE_OP LaneReals operator*(LaneReals a, LaneReals b) { return a.v * b.v; }
    friend FP_LANE_OP LaneReals operator/(LaneReals a, LaneReals b) { return a.v / b.v; }
    friend FP_LANE_OP LaneReals operator-(LaneReals a) { return -a.v; }
    FP_LANE_OP LaneReals& operator+=(LaneReals o) { v += o.v; return *this; }
    FP_LANE_OP LaneReals& operator*=(LaneReals o) { v *= o.v; return *this; }

    // Ordered comparisons, as E's: false in a lane where either side is NaN (!= true there).
    friend FP_LANE_OP Mask operator<(LaneReals a, LaneReals b) { return compare<Compare::less>(a, b); }
    friend FP_LANE_OP Mask operator<=(LaneReals a, LaneReals b) { return compare<Compare::lessEqual>(a, b); }
    friend FP_LANE_OP Mask operator>(LaneReals a, LaneReals b) { return compare<Compare::less>(b, a); }
    friend FP_LANE_OP Mask operator>=(LaneReals a, LaneReals b) { return compare<Compare::lessEqual>(b, a); }
    friend FP_LANE_OP Mask operator==(LaneReals a, LaneReals b) { return compare<Compare::equal>(a, b); }
    friend FP_LANE_OP Mask operator!=(LaneReals a, LaneReals b) { return compare<Compare::notEqual>(a, b); }

    /// m ? a : b, lane by lane.
    friend FP_LANE_OP LaneReals ifThenElse(Mask m, LaneReals a, LaneReals b) {
        return lanes_detail::selected(m.v, a.v, b.v);
    }
    friend FP_LANE_OP LaneReals sqrtOf(LaneReals a) {
        return map(a, [](E x) { return fp::sqrtOf(x); });
    }
    friend FP_LANE_OP LaneReals floorOf(LaneReals a) {
        return map(a, [](E x) { return fp::floorOf(x); });
    }
    /// |a| and |mag| with sign's sign bit: the sign bit cleared or copied, as fabs and copysign.
    friend FP_LANE_OP LaneReals absOf(LaneReals a) { return (V)((IntBits)a.v & ~kSign); }
    friend FP_LANE_OP LaneReals copySignOf(LaneReals mag, LaneReals sign) {
        return (V)(((IntBits)mag.v & ~kSign) | ((IntBits)sign.v & kSign));
    }
    friend FP_LANE_OP Mask isFiniteOf(LaneReals a) { return absOf(a) < LaneReals(kInfinity); }
    friend FP_LANE_OP Mask isInfOf(LaneReals a) { return absOf(a) == LaneReals(kInfinity); }
    friend FP_LANE_OP E laneOf(LaneReals a, int i) { return a.v[i]; }
    /// Math.h's saturateOf, lane by lane.
    friend FP_LANE_OP LaneReals saturate(LaneReals a) { return saturateOf(a); }

private:
    using Compare = lanes_detail::Compare;
    template <Compare C>
    static FP_LANE_OP Mask compare(LaneReals a, LaneReals b) {
        return {(Bits)lanes_detail::compared<C>(a.v, b.v)};  // double lanes compare to long, not long long
    }
    /// Math.h's `fn` of each lane: a loop the vectoriser makes one instruction (see the top).
    template <class Fn>
    static FP_LANE_OP LaneReals map(LaneReals a, Fn fn) {
        V r = a.v;
        for (int i = 0; i < N; ++i) r[i] = fn(a.v[i]);
        return r;
    }
    using Bits = decltype(Mask{}.v);  // a comparison's outcome
    using BitsE = std::conditional_t<sizeof(E) == 4, int, long long>;
    typedef BitsE IntBits __attribute__((vector_size(sizeof(V))));  // integers as wide as E
    static constexpr BitsE kSign = std::numeric_limits<BitsE>::min();  // the sign bit alone
    static constexpr E kInfinity = __builtin_inf();
};
template <int N>
using LaneFloat = LaneReals<typename LaneVectors<N>::F, float, LaneMask<N>, N>;

/// Two halves of lanes (H: a LaneReals or its mask) that act as one vector of twice the lanes:
/// N doubles are twice as wide as N floats, so the double lanes of an N-float kernel are two
/// target-wide vectors (GCC lowers a generic vector wider than the target lane by lane).
template <class H>
struct LanePair {
    H lo, hi;

    LanePair() = default;
    FP_LANE_OP LanePair(H l, H h) : lo(l), hi(h) {}
    /// Every lane `x`.
    template <class E, class = std::enable_if_t<std::is_arithmetic_v<E>>>
    FP_LANE_OP LanePair(E x) : lo(x), hi(x) {}

    friend FP_LANE_OP LanePair operator+(LanePair a, LanePair b) { return {a.lo + b.lo, a.hi + b.hi}; }
    friend FP_LANE_OP LanePair operator-(LanePair a, LanePair b) { return {a.lo - b.lo, a.hi - b.hi}; }
    friend FP_LANE_OP LanePair operator*(LanePair a, LanePair b) { return {a.lo * b.lo, a.hi * b.hi}; }
    friend FP_LANE_OP LanePair operator/(LanePair a, LanePair b) { return {a.lo / b.lo, a.hi / b.hi}; }
    friend FP_LANE_OP LanePair operator-(LanePair a) { return {-a.lo, -a.hi}; }
    friend FP_LANE_OP auto operator==(LanePair a, LanePair b) { return pairOf(a.lo == b.lo, a.hi == b.hi); }
    friend FP_LANE_OP auto operator<(LanePair a, LanePair b) { return pairOf(a.lo < b.lo, a.hi < b.hi); }
    friend FP_LANE_OP LanePair operator&(LanePair a, LanePair b) { return {a.lo & b.lo, a.hi & b.hi}; }
    friend FP_LANE_OP LanePair operator|(LanePair a, LanePair b) { return {a.lo | b.lo, a.hi | b.hi}; }
    friend FP_LANE_OP LanePair operator!(LanePair a) { return {!a.lo, !a.hi}; }
    template <class M>
    friend FP_LANE_OP LanePair ifThenElse(LanePair<M> m, LanePair a, LanePair b) {
        return {ifThenElse(m.lo, a.lo, b.lo), ifThenElse(m.hi, a.hi, b.hi)};
    }
    friend FP_LANE_OP LanePair floorOf(LanePair a) { return {floorOf(a.lo), floorOf(a.hi)}; }
    friend FP_LANE_OP LanePair sqrtOf(LanePair a) { return {sqrtOf(a.lo), sqrtOf(a.hi)}; }
    friend FP_LANE_OP LanePair absOf(LanePair a) { return {absOf(a.lo), absOf(a.hi)}; }
    friend FP_LANE_OP auto isInfOf(LanePair a) { return pairOf(isInfOf(a.lo), isInfOf(a.hi)); }

private:
    template <class M>
    static FP_LANE_OP LanePair<M> pairOf(M l, M h) { return {l, h}; }
};

template <int N>
using LaneDoubleHalf = LaneReals<typename LaneVectors<N>::DH, double,
                                 LaneMaskOf<typename LaneVectors<N>::LH, N / 2>, N / 2>;
/// N doubles: the double lanes of an N-float kernel (sinCos, a device Z in double).
template <int N>
using LaneDouble = LanePair<LaneDoubleHalf<N>>;

/// The outcome of a comparison of N double lanes (two halves) as N float lanes' mask.
template <class V, int Half, bool Bits>
FP_LANE_OP LaneMask<2 * Half> toFloatMask(LanePair<LaneMaskOf<V, Half, Bits>> m) {
    constexpr int N = 2 * Half;
    if constexpr (Bits) {
        return {typename LaneMask<N>::Word(unsigned(m.lo.v) | (unsigned(m.hi.v) << Half))};
    } else {
        typedef int HalfInts __attribute__((vector_size(Half * sizeof(int))));
        return {lanes_detail::pick(__builtin_convertvector(m.lo.v, HalfInts),
                                   __builtin_convertvector(m.hi.v, HalfInts), std::make_index_sequence<N>{})};
    }
}

/// A float kernel's companion types and lane count for N float lanes (Math.h: float's).
template <class V, class M, int N>
struct LaneTypes<LaneReals<V, float, M, N>> {
    using Int = LaneInt<N>;
    using UInt = LaneUInt<N>;
    using Double = LaneDouble<N>;
    using Mask = M;
    static constexpr int kCount = N;
    /// 0, 1, …, N − 1.
    static FP_LANE_OP UInt indices() {
        UInt r(0u);
        for (int i = 0; i < N; ++i) r.v[i] = uint32_t(i);
        return r;
    }
};

// Conversions between lane types: the C++ conversion of each lane (toInt truncates; the caller
// keeps the value in int's range, as floorToIntOf does).
template <int N>
FP_LANE_OP LaneDouble<N> toDouble(LaneFloat<N> a) {
    using DH = typename LaneVectors<N>::DH;
    constexpr auto half = std::make_index_sequence<N / 2>{};
    return {__builtin_convertvector(lanes_detail::pick(a.v, a.v, half), DH),
            __builtin_convertvector(lanes_detail::pick(a.v, a.v, lanes_detail::shifted<N / 2>(half)), DH)};
}
template <class V, class M, int Half, int N = 2 * Half>
FP_LANE_OP LaneFloat<N> toFloat(LanePair<LaneReals<V, double, M, Half>> a) {
    using FH = typename LaneVectors<N>::FH;
    return lanes_detail::pick(__builtin_convertvector(a.lo.v, FH), __builtin_convertvector(a.hi.v, FH),
                              std::make_index_sequence<N>{});
}
template <class V, class E, int N>
FP_LANE_OP LaneFloat<N> toFloat(LaneIntegers<V, E, N> a) { return __builtin_convertvector(a.v, typename LaneVectors<N>::F); }
template <int N>
FP_LANE_OP LaneInt<N> toInt(LaneFloat<N> a) { return __builtin_convertvector(a.v, typename LaneVectors<N>::I); }
/// The floats whose bits are the lanes of `bits` (std::bit_cast lane by lane).
template <int N>
FP_LANE_OP LaneFloat<N> floatFromBits(LaneInt<N> bits) { return (typename LaneVectors<N>::F)bits.v; }

#if defined(__x86_64__) && !defined(__clang__)
namespace lanes_detail {
/// AVX-512's 16-lane gather of data[index], every lane. Like compared/selected, it carries the
/// target itself (the builtin's mask argument is a mask register) and is inlined by the flatten
/// of the AVX-512 function that runs a kernel.
__attribute__((target("avx512f"))) inline LaneVectors<16>::F gather16(const float* data,
                                                                     LaneVectors<16>::I index) {
    return __builtin_ia32_gathersiv16sf(LaneVectors<16>::F{}, data, index, (unsigned short)0xFFFF, 4);
}
}  // namespace lanes_detail
#endif

/// Each lane's texel of `p` at (x, y) of that lane (PlaneView::at lane by lane). 8 and 16 lanes
/// are the AVX2 and AVX-512 builds' widths, so there the read is the hardware gather (GCC's
/// builtins; a load a lane made SSGI's march 3–15 % slower on AMD Zen 3 with AVX2, and SSGI 1.5×
/// slower with AVX-512); 4 lanes (SSE4, which has no gather) read a lane at a time.
template <int N>
FP_LANE_OP LaneFloat<N> gatherAt(const PlaneView& p, LaneInt<N> x, LaneInt<N> y) {
    const LaneInt<N> index = y * int(p.stride) + x;
#if defined(__x86_64__) && !defined(__clang__)
    using F = typename LaneVectors<N>::F;
    if constexpr (N == 8)
        return __builtin_ia32_gathersiv8sf(F{}, p.data, index.v, (F)(index.v == index.v), 4);
    if constexpr (N == 16)
        return lanes_detail::gather16(p.data, index.v);
#endif
    LaneFloat<N> r(0.0f);
    for (int i = 0; i < N; ++i) r.v[i] = p.data[index.v[i]];
    return r;
}

#if defined(__x86_64__) && !defined(__clang__)
namespace lanes_detail {
/// AVX-512's compress of the lanes of v where mask m holds, to the low lanes (zeros above): in
/// a register, then stored whole by the caller (a compress straight to memory is microcoded and
/// slow on AMD's Zen 4).
__attribute__((target("avx512f"))) inline LaneVectors<16>::F compressed16(LaneVectors<16>::F v, unsigned short m) {
    return __builtin_ia32_compresssf512_mask(v, LaneVectors<16>::F{}, m);
}
__attribute__((target("avx512f"))) inline LaneVectors<16>::I compressed16(LaneVectors<16>::I v, unsigned short m) {
    return __builtin_ia32_compresssi512_mask(v, LaneVectors<16>::I{}, m);
}
__attribute__((target("avx512f"))) inline LaneVectors<16>::U compressed16(LaneVectors<16>::U v, unsigned short m) {
    return LaneVectors<16>::U(compressed16(LaneVectors<16>::I(v), m));
}
}  // namespace lanes_detail
#endif

/// The lanes of `v` (a LaneFloat, LaneInt or LaneUInt) where `m` holds, in lane order, to out[0…]; returns
/// how many. It writes N values (those past the count are scratch): `out` has room for N. With
/// AVX-512 one compress; otherwise lane by lane without a branch.
template <class Lanes, class M, class E>
FP_LANE_OP int compressStore(Lanes v, M m, E* out) {
    constexpr int N = int(sizeof(v.v) / sizeof(E));
#if defined(__x86_64__) && !defined(__clang__)
    if constexpr (N == 16 && lanes_detail::kBitMasks) {
        const auto packed = lanes_detail::compressed16(v.v, m.v);
        std::memcpy(out, &packed, sizeof packed);
        return countLanes(m);
    }
#endif
    int k = 0;
    for (int i = 0; i < N; ++i) {
        out[k] = v.v[i];
        k += laneOf(m, i) ? 1 : 0;
    }
    return k;
}

/// Three planes' floats at `x`, `y`, `z` (N each) as a vector of N points.
template <class T>
FP_LANE_OP Vec3T<T> loadLanes3(const float* x, const float* y, const float* z) {
    return {T::load(x), T::load(y), T::load(z)};
}

template <class T>
FP_LANE_OP void storeLanes3(const Vec3T<T>& a, float* x, float* y, float* z) {
    a.x.store(x);
    a.y.store(y);
    a.z.store(z);
}

#undef FP_LANE_OP

}  // namespace fp
