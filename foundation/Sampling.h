#pragma once
// Sampling primitives shared by the ray-traced passes and the reference tracer (algorithms §1.9):
// the branchless orthonormal basis, cosine-weighted hemisphere directions from the concentric
// disk, and GGX visible-normal sampling with its pdf.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/SinCos.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace fp {

/// Orthonormal basis (t, b) around unit n (Duff et al. 2017, branchless; algorithms §1.9); T:
/// float or float lanes (LaneFloat.h).
template <class T>
FP_HD inline void orthonormalBasis(const Vec3T<T>& n, Vec3T<T>& t, Vec3T<T>& b) {
    const T s = ifThenElse(n.z >= 0.0f, T(1.0f), T(-1.0f));
    const T a = -1.0f / (s + n.z);
    const T c = n.x * n.y * a;
    t = {1.0f + s * a * n.x * n.x, s * c, -s * n.x};
    b = {c, s + a * n.y * n.y, -n.y};
}

/// Van der Corput radical inverse of i in base 2 (the bits of i mirrored behind the binary point):
/// the second coordinate of the Hammersley set that Unreal's preintegration loops use.
inline double radicalInverse2(uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
    i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
    i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
    i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
    return double(i) / 4294967296.0;
}

/// Shirley–Chiu concentric map of the unit square onto the unit disk (area-preserving); T: float
/// or float lanes (LaneFloat.h), each lane choosing its octant's ratio by a select.
template <class T>
FP_HD inline void concentricDisk(T u, T v, T& x, T& y) {
    const T a = 2.0f * u - 1.0f, b = 2.0f * v - 1.0f;
    const MaskOf<T> wide = absOf(a) > absOf(b);
    const T r = ifThenElse(wide, a, b);
    const T ratio = ifThenElse(wide, b, a) / r;
    const T phi = ifThenElse(wide, (kPiF / 4.0f) * ratio, (kPiF / 2.0f) - (kPiF / 4.0f) * ratio);
    T sinPhi, cosPhi;
    sinCos(phi, sinPhi, cosPhi);  // the same bits on the CPU, in SIMD lanes and on the GPU
    const MaskOf<T> centre = (a == 0.0f) & (b == 0.0f);
    x = ifThenElse(centre, T(0.0f), r * cosPhi);
    y = ifThenElse(centre, T(0.0f), r * sinPhi);
}

/// Cosine-weighted direction around unit n: a concentric-disk point lifted to the hemisphere
/// (pdf = cosθ/π), as Unreal's SSGI builds its rays (algorithms §4.4).
FP_HD inline Vec3f cosineHemisphere(const Vec3f& n, float u, float v) {
    float x, y;
    concentricDisk(u, v, x, y);
    const float z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
    Vec3f t, b;
    orthonormalBasis(n, t, b);
    return normalize(t * x + b * y + n * z);
}

/// Smith's masking term G1 for GGX with α² = a2, at cosine NoX.
FP_HD inline float smithG1(float a2, float NoX) {
    return 2.0f * NoX / (NoX + std::sqrt(a2 + (1.0f - a2) * NoX * NoX));
}

/// A GGX half vector distributed as the normals visible from V (Heitz 2018), for unit n and
/// unit V above it, roughness α. The pdf of the reflected direction is D·G1(V)/(4·NoV). The angle
/// goes through sinCos, so SSR's rays are the same bits on the CPU and the GPU; T: float or float
/// lanes (LaneFloat.h), each lane the same operations in the same order.
template <class T>
FP_HD inline Vec3T<T> sampleGgxVisibleNormalOf(const Vec3T<T>& n, const Vec3T<T>& V, T alpha, T u,
                                               T v) {
    using V3 = Vec3T<T>;
    V3 t, b;
    orthonormalBasis(n, t, b);
    // V in the tangent frame, stretched to the hemisphere configuration.
    const V3 vl{dot(V, t), dot(V, b), dot(V, n)};
    const V3 vh = normalize(V3{alpha * vl.x, alpha * vl.y, vl.z});
    const T lensq = vh.x * vh.x + vh.y * vh.y;
    const V3 t1 = ifThenElse(lensq > 0.0f, V3{-vh.y, vh.x, T(0.0f)} / sqrtOf(lensq),
                             V3{T(1.0f), T(0.0f), T(0.0f)});
    const V3 t2 = cross(vh, t1);
    const T r = sqrtOf(u), phi = 2.0f * kPiF * v;
    T sinPhi, cosPhi;
    sinCos<T>(phi, sinPhi, cosPhi);
    const T p1 = r * cosPhi;
    const T s = 0.5f * (1.0f + vh.z);
    const T p2 = (1.0f - s) * sqrtOf(maxLike(T(0.0f), 1.0f - p1 * p1)) + s * r * sinPhi;
    const V3 nh = t1 * p1 + t2 * p2 + vh * sqrtOf(maxLike(T(0.0f), 1.0f - p1 * p1 - p2 * p2));
    // Unstretch back to the ellipsoid configuration, then to world space.
    const V3 hl = normalize(V3{alpha * nh.x, alpha * nh.y, maxLike(T(0.0f), nh.z)});
    return normalize(t * hl.x + b * hl.y + n * hl.z);
}
FP_HD inline Vec3f sampleGgxVisibleNormal(const Vec3f& n, const Vec3f& V, float alpha, float u, float v) {
    return sampleGgxVisibleNormalOf<float>(n, V, alpha, u, v);
}

/// v mirrored about unit n; T: float or float lanes.
template <class T>
FP_HD inline Vec3T<T> reflect(const Vec3T<T>& v, const Vec3T<T>& n) {
    return n * (2.0f * dot(v, n)) - v;
}

FP_HD inline float luminance(const Vec3f& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace fp
