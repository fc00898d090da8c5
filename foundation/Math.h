#pragma once
// Small vector and matrix types. Doubles where precision matters (camera, world positions far
// from the origin); floats in per-pixel kernels, which work camera-relative (algorithms §1.2–1.3).
#include "foundation/HostDevice.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace fp {

template <class T>
struct Vec3T {
    T x = 0, y = 0, z = 0;
    constexpr Vec3T() = default;
    FP_HD constexpr Vec3T(T a, T b, T c) : x(a), y(b), z(c) {}
    template <class U>
    FP_HD constexpr explicit Vec3T(const Vec3T<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
    FP_HD constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    FP_HD constexpr Vec3T operator+(const Vec3T& o) const { return {x + o.x, y + o.y, z + o.z}; }
    FP_HD constexpr Vec3T operator-(const Vec3T& o) const { return {x - o.x, y - o.y, z - o.z}; }
    FP_HD constexpr Vec3T operator-() const { return {-x, -y, -z}; }
    FP_HD constexpr Vec3T operator*(T s) const { return {x * s, y * s, z * s}; }
    FP_HD constexpr Vec3T operator*(const Vec3T& o) const { return {x * o.x, y * o.y, z * o.z}; }
    FP_HD constexpr Vec3T operator/(T s) const { return {x / s, y / s, z / s}; }
    FP_HD Vec3T& operator+=(const Vec3T& o) { x += o.x; y += o.y; z += o.z; return *this; }
    FP_HD Vec3T& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
};
using Vec3f = Vec3T<float>;
using Vec3d = Vec3T<double>;

// The primitives a per-pixel kernel written once for float and for LaneFloat (LaneFloat.h, a
// SIMD vector of pixels) shares: a comparison gives a mask (bool here), and the kernel chooses
// with ifThenElse, asks anyLane and takes maxLike (std::max's rule, NaN included) and sqrtOf
// instead of `?:`, `if`, std::max and std::sqrt. LaneFloat defines the same names for lanes.
FP_HD constexpr float ifThenElse(bool m, float a, float b) { return m ? a : b; }
FP_HD constexpr double ifThenElse(bool m, double a, double b) { return m ? a : b; }
FP_HD constexpr bool anyLane(bool m) { return m; }
FP_HD constexpr int countLanes(bool m) { return m ? 1 : 0; }
/// A comparison of doubles' outcome as the float lanes' mask (LaneFloat.h: the two halves joined).
FP_HD constexpr bool toFloatMask(bool m) { return m; }
FP_HD inline float sqrtOf(float x) { return std::sqrt(x); }
FP_HD inline double sqrtOf(double x) { return std::sqrt(x); }
FP_HD inline float floorOf(float x) { return std::floor(x); }
FP_HD inline double floorOf(double x) { return std::floor(x); }
FP_HD inline float absOf(float x) { return std::fabs(x); }
FP_HD inline double absOf(double x) { return std::fabs(x); }
FP_HD inline float copySignOf(float mag, float sign) { return std::copysign(mag, sign); }
FP_HD inline bool isFiniteOf(float x) { return std::isfinite(x); }
FP_HD inline bool isInfOf(double x) { return std::isinf(x); }
// Conversions (LaneFloat.h: lane by lane). toInt truncates; its caller keeps x in int's range.
FP_HD constexpr double toDouble(float x) { return x; }
FP_HD constexpr float toFloat(double x) { return float(x); }
FP_HD constexpr float toFloat(int x) { return float(x); }
FP_HD constexpr float toFloat(uint32_t x) { return float(x); }
FP_HD constexpr int toInt(float x) { return int(x); }
FP_HD inline float floatFromBits(int bits) { return std::bit_cast<float>(bits); }
/// One value's lane 0: itself (LaneFloat.h: lane i of a vector).
FP_HD constexpr float laneOf(float v, int) { return v; }
FP_HD constexpr bool laneOf(bool v, int) { return v; }
FP_HD constexpr int laneOf(int v, int) { return v; }
/// Lane i of three components (a Vec3f of lanes: one point of the vector).
template <class T>
FP_HD constexpr Vec3f laneOf(const Vec3T<T>& a, int i) {
    return {laneOf(a.x, i), laneOf(a.y, i), laneOf(a.z, i)};
}
/// std::max(a, b): (a < b) ? b : a.
template <class T>
FP_HD constexpr T maxLike(T a, T b) { return ifThenElse(a < b, b, a); }
/// std::min(a, b): (b < a) ? b : a.
template <class T>
FP_HD constexpr T minLike(T a, T b) { return ifThenElse(b < a, b, a); }

/// A kernel's number type T and its companions: integers, unsigned integers and doubles with as
/// many lanes, the outcome of a comparison, and the lane count (LaneFloat.h: for N lanes).
template <class T>
struct LaneTypes;
template <>
struct LaneTypes<float> {
    using Int = int;
    using UInt = uint32_t;
    using Double = double;
    using Mask = bool;
    static constexpr int kCount = 1;
    /// Each lane's index: 0, 1, …, kCount − 1.
    FP_HD static constexpr UInt indices() { return 0; }
};
template <class T>
using IntOf = typename LaneTypes<T>::Int;
template <class T>
using UIntOf = typename LaneTypes<T>::UInt;
template <class T>
using DoubleOf = typename LaneTypes<T>::Double;
template <class T>
using MaskOf = typename LaneTypes<T>::Mask;
template <class T>
constexpr int kLanesOf = LaneTypes<T>::kCount;
/// m ? a : b for each component (m: one mask for all three).
template <class M, class T>
FP_HD constexpr Vec3T<T> ifThenElse(const M& m, const Vec3T<T>& a, const Vec3T<T>& b) {
    return {ifThenElse(m, a.x, b.x), ifThenElse(m, a.y, b.y), ifThenElse(m, a.z, b.z)};
}

template <class T>
FP_HD constexpr T dot(const Vec3T<T>& a, const Vec3T<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T>
FP_HD constexpr Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
FP_HD FP_HOT_INLINE T length(const Vec3T<T>& a) { return sqrtOf(dot(a, a)); }
template <class T>
FP_HD FP_HOT_INLINE Vec3T<T> normalize(const Vec3T<T>& a) {
    const T l = length(a);
    return ifThenElse(l > T(0), a / l, Vec3T<T>{});
}

/// Clamp to [0, 1] (HLSL saturate): v < 0 ? 0 : (v > 1 ? 1 : v), NaN kept; T: float or lanes.
template <class T>
FP_HD constexpr T saturateOf(T v) { return ifThenElse(v < T(0.0f), T(0.0f), ifThenElse(v > T(1.0f), T(1.0f), v)); }
FP_HD inline float saturate(float v) { return saturateOf(v); }

/// Row-major 4×4 double matrix acting on column vectors: p' = M·p.
struct Mat4d {
    std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    double& operator()(int r, int c) { return m[r * 4 + c]; }
    double operator()(int r, int c) const { return m[r * 4 + c]; }
    Mat4d operator*(const Mat4d& o) const {
        Mat4d r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                double s = 0;
                for (int k = 0; k < 4; ++k) s += (*this)(i, k) * o(k, j);
                r(i, j) = s;
            }
        return r;
    }
    /// Transforms a point (w = 1) and returns the homogeneous result.
    std::array<double, 4> apply(const Vec3d& p) const {
        std::array<double, 4> r{};
        for (int i = 0; i < 4; ++i)
            r[i] = (*this)(i, 0) * p.x + (*this)(i, 1) * p.y + (*this)(i, 2) * p.z + (*this)(i, 3);
        return r;
    }
    Mat4d transposed() const {
        Mat4d r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) r(i, j) = (*this)(j, i);
        return r;
    }
    static Mat4d zero() {
        Mat4d r;
        r.m.fill(0.0);
        return r;
    }
};

/// General 4×4 inverse (cofactors). Throws nothing: a singular matrix returns all zeros.
Mat4d inverse(const Mat4d& a);

constexpr double kPi = 3.14159265358979323846;
constexpr float kPiF = 3.14159265358979323846f;

}  // namespace fp
