#pragma once
// The number type that lets a kernel be written once for one pixel and for a SIMD vector of
// pixels. A kernel templated on its number type T runs with T = float for one pixel (the CPU's
// scalar reference and the CUDA thread) and with T = LaneFloat<N> for N pixels at once on the CPU.
// Its comparisons give a mask (bool for float, LaneMask<N> here), which it combines with
// ifThenElse, anyLane, maxLike and saturate (Math.h for float, the friends below for lanes)
// instead of `?:`, `if` or std::max: the only spellings both types share.
//
// LaneFloat is a GCC vector (vector_size): the compiler lowers its operators to the instructions
// of the function they end up in. A per-instruction-set function (Highway's foreach_target.h
// compiles one per x86 target) that is __attribute__((flatten)) inlines the whole templated
// kernel, so the kernel becomes SSE4, AVX2 or AVX-512 code there. Every operation is the IEEE
// operation the scalar code does, lane by lane, in the same order (no contraction: the build sets
// -ffp-contract=off), so each lane gives the scalar code's bits. sqrtOf is a loop of
// __builtin_sqrtf that the vectoriser turns into one vector square root when the file is built
// with -fno-math-errno (the result is the same correctly rounded root either way).
//
// Host only: the CUDA kernels instantiate the same templates with float.
#include "foundation/Math.h"

#include <cstring>

#if defined(__CUDACC__)
#error "LaneFloat.h is the CPU's lane type; CUDA kernels run the templates with float"
#endif

namespace fp {

template <int N>
struct LaneVectors;  // the GCC vector types of N floats and N ints (vector_size takes no template value)
template <>
struct LaneVectors<4> {
    typedef float F __attribute__((vector_size(16)));
    typedef int I __attribute__((vector_size(16)));
};
template <>
struct LaneVectors<8> {
    typedef float F __attribute__((vector_size(32)));
    typedef int I __attribute__((vector_size(32)));
};
template <>
struct LaneVectors<16> {
    typedef float F __attribute__((vector_size(64)));
    typedef int I __attribute__((vector_size(64)));
};

#define FP_LANE_OP __attribute__((always_inline)) inline

/// N comparisons' outcomes: all bits set in a lane where true (GCC's vector comparison result).
template <int N>
struct LaneMask {
    typename LaneVectors<N>::I v;

    friend FP_LANE_OP LaneMask operator!(LaneMask a) { return {a.v == 0}; }
    friend FP_LANE_OP LaneMask operator|(LaneMask a, LaneMask b) { return {a.v | b.v}; }
    friend FP_LANE_OP LaneMask operator&(LaneMask a, LaneMask b) { return {a.v & b.v}; }
    friend FP_LANE_OP bool anyLane(LaneMask a) {
        unsigned long long words[N / 2];
        std::memcpy(words, &a.v, sizeof words);
        unsigned long long any = 0;
        for (unsigned long long w : words) any |= w;
        return any != 0;
    }
    /// Lane i's outcome (0 or 1) into out[i].
    FP_LANE_OP void store(bool* out) const {
        for (int i = 0; i < N; ++i) out[i] = v[i] != 0;
    }
};

/// N floats, one a lane; every operator is the float operator lane by lane.
template <int N>
struct LaneFloat {
    using V = typename LaneVectors<N>::F;
    using Mask = LaneMask<N>;
    static constexpr int kLanes = N;
    V v;

    LaneFloat() = default;
    FP_LANE_OP constexpr LaneFloat(V x) : v(x) {}
    /// Every lane `x`: x − 0 keeps −0 and NaN as they are (0 + x would turn −0 into +0).
    FP_LANE_OP constexpr LaneFloat(float x) : v(x - V{}) {}

    /// N floats from `p` (unaligned) and back.
    static FP_LANE_OP LaneFloat load(const float* p) {
        LaneFloat r;
        std::memcpy(&r.v, p, sizeof r.v);
        return r;
    }
    FP_LANE_OP void store(float* p) const { std::memcpy(p, &v, sizeof v); }

    friend FP_LANE_OP LaneFloat operator+(LaneFloat a, LaneFloat b) { return a.v + b.v; }
    friend FP_LANE_OP LaneFloat operator-(LaneFloat a, LaneFloat b) { return a.v - b.v; }
    friend FP_LANE_OP LaneFloat operator*(LaneFloat a, LaneFloat b) { return a.v * b.v; }
    friend FP_LANE_OP LaneFloat operator/(LaneFloat a, LaneFloat b) { return a.v / b.v; }
    friend FP_LANE_OP LaneFloat operator-(LaneFloat a) { return -a.v; }
    FP_LANE_OP LaneFloat& operator+=(LaneFloat o) { v += o.v; return *this; }
    FP_LANE_OP LaneFloat& operator*=(LaneFloat o) { v *= o.v; return *this; }

    // Ordered comparisons, as float's: false in a lane where either side is NaN.
    friend FP_LANE_OP Mask operator<(LaneFloat a, LaneFloat b) { return {a.v < b.v}; }
    friend FP_LANE_OP Mask operator<=(LaneFloat a, LaneFloat b) { return {a.v <= b.v}; }
    friend FP_LANE_OP Mask operator>(LaneFloat a, LaneFloat b) { return {a.v > b.v}; }
    friend FP_LANE_OP Mask operator>=(LaneFloat a, LaneFloat b) { return {a.v >= b.v}; }

    /// m ? a : b, lane by lane.
    friend FP_LANE_OP LaneFloat ifThenElse(Mask m, LaneFloat a, LaneFloat b) { return m.v ? a.v : b.v; }
    friend FP_LANE_OP LaneFloat sqrtOf(LaneFloat a) {
        V r;
        for (int i = 0; i < N; ++i) r[i] = __builtin_sqrtf(a.v[i]);
        return r;
    }
    /// Math.h's saturate (v < 0 ? 0 : (v > 1 ? 1 : v)), lane by lane.
    friend FP_LANE_OP LaneFloat saturate(LaneFloat a) {
        return ifThenElse(a < 0.0f, 0.0f, ifThenElse(a > 1.0f, 1.0f, a));
    }
};

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
