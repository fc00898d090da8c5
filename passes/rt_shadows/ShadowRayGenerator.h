#pragma once
// Shadow-ray directions towards one light, as Unreal's ray-traced shadow generators choose them
// (algorithms §9.2): a concentric-disk sample of the directional light's cone (SourceRadius =
// sin(½·LightSourceAngle)), a uniform sample of the solid angle of a sphere light, a uniform point
// of a rect light. Positions are relative to the RayScene origin (camera-relative). The maths is
// FP_HD: the CPU's scalar reference and the GPU's kernel run the same functions.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/Sampling.h"
#include "foundation/Scene.h"
#include "foundation/SinCos.h"
#include "foundation/UnrealRandom.h"

#include <cmath>

namespace fp {

/// A shadow ray's direction and length; T: float, or float lanes (LaneFloat.h).
template <class T>
struct ShadowDirectionOf {
    Vec3T<T> dir;    //!< unit direction of the shadow ray
    T tfar = 0.0f;   //!< where the ray stops: the light's surface, or far away for directional
};
using ShadowDirection = ShadowDirectionOf<float>;

/// The light as its shadow rays see it, in the float terms the functions below compute with.
struct ShadowLightShape {
    LightType type = LightType::Point;
    Vec3f position;           //!< relative to the RayScene origin
    Vec3f toLight;            //!< directional: unit vector towards the light
    Vec3f toLightT, toLightB;  //!< directional: orthonormalBasis(toLight)
    Vec3f axis;               //!< spot axis (direction of travel), rect emission normal
    Vec3f halfU, halfV;       //!< rect half extents
    float cosOuter = -1.0f;   //!< spot: cos of the outer cone angle
    float sourceRadius = 0;   //!< directional: sin(½ angle)
    float radius = 0;         //!< point/spot sphere radius
    /// Attenuation radius as a float bound: a float distance d is beyond the (double) radius
    /// exactly when d > reachBound (the largest float not above it); +∞ when unlimited.
    float reachBound = 0;
    static constexpr float kDirectionalTraceDistance = 1e27f;  // algorithms §9.2: "infinite"
};

// The functions below take T = float (one pixel: the scalar reference, the GPU) or float lanes
// (LaneFloat.h: a vector of pixels, ShadowLanes.cpp); a lane's result is the scalar one's bits.

/// False when the light sends nothing to `p`: beyond its attenuation radius, outside a spot's
/// cone, behind a rect light (algorithms §9.2, "local lights: rays longer than the attenuation
/// radius are skipped"). Such pixels are skipped.
template <class T>
FP_HD inline MaskOf<T> lightReaches(const ShadowLightShape& s, const Vec3T<T>& p) {
    if (s.type == LightType::Directional) return !MaskOf<T>{};
    const Vec3T<T> d = Vec3T<T>(s.position) - p;
    const MaskOf<T> inRange = !(length(d) > s.reachBound);
    if (s.type == LightType::Spot) return inRange & (dot(normalize(-d), Vec3T<T>(s.axis)) > s.cosOuter);
    if (s.type == LightType::Rect) return inRange & (dot(-d, Vec3T<T>(s.axis)) > 0.0f);
    return inRange;
}

/// Unit direction from `p` to the light's centre, the L of N·L culling and biasing.
template <class T>
FP_HD inline Vec3T<T> lightCentreDirection(const ShadowLightShape& s, const Vec3T<T>& p) {
    if (s.type == LightType::Directional) return Vec3T<T>(s.toLight);
    return normalize(Vec3T<T>(s.position) - p);
}

/// Ray towards the sample (u, v) ∈ [0,1)² of the light's extent, from the biased origin `o`.
template <class T>
FP_HD inline ShadowDirectionOf<T> sampleLight(const ShadowLightShape& l, const Vec3T<T>& o, T u, T v) {
    using V3 = Vec3T<T>;
    ShadowDirectionOf<T> s;
    if (l.type == LightType::Directional) {
        T dx, dy;
        ue::concentricDisk(u, v, dx, dy);
        s.dir = normalize(V3(l.toLight) + (V3(l.toLightT) * dx + V3(l.toLightB) * dy) * T(l.sourceRadius));
        s.tfar = ShadowLightShape::kDirectionalTraceDistance;
        return s;
    }
    if (l.type == LightType::Rect) {
        const V3 q = V3(l.position) + V3(l.halfU) * (2.0f * u - 1.0f) + V3(l.halfV) * (2.0f * v - 1.0f);
        const V3 d = q - o;
        const T dist = length(d);
        s.dir = d / dist;
        // Stop just short of the emitter: its own quad, when it is in the geometry, is no occluder.
        s.tfar = dist * (1.0f - 1e-4f);
        return s;
    }
    // Point and spot lights.
    const V3 d = V3(l.position) - o;
    const T dist = length(d);
    const V3 L = d / dist;
    const float r = l.radius;
    // A pixel inside the sphere: straight at the centre, nothing to trace.
    const MaskOf<T> inside = dist <= r;
    if (r <= 0.0f) {  // a point
        s.dir = L;
        s.tfar = ifThenElse(inside, T(0.0f), dist);
        return s;
    }
    // Uniform in the solid angle the sphere subtends (algorithms §9.2, inferred generator).
    const T sinMax = r / dist, cosMaxSq = 1.0f - sinMax * sinMax;
    const T cosMax = sqrtOf(maxLike(T(0.0f), cosMaxSq));
    const T cosT = 1.0f - u * (1.0f - cosMax);
    const T sinTSq = 1.0f - cosT * cosT;
    const T sinT = sqrtOf(maxLike(T(0.0f), sinTSq));
    T sinPhi, cosPhi;
    sinCos(2.0f * kPiF * v, sinPhi, cosPhi);
    V3 t, b;
    orthonormalBasis(L, t, b);
    const V3 cone = normalize(t * (sinT * cosPhi) + b * (sinT * sinPhi) + L * cosT);
    // Distance to the near side of the sphere along the ray.
    const T along = dist * cosT;
    const T chordSq = r * r - dist * dist * sinT * sinT;
    const T near = along - sqrtOf(maxLike(T(0.0f), chordSq));
    s.dir = ifThenElse(inside, L, cone);
    s.tfar = ifThenElse(inside, T(0.0f), maxLike(T(0.0f), near));
    return s;
}

/// The light as its shadow rays see it, around `lightOrigin`: the scene origin of the RayScene the
/// rays go into (positions are relative).
ShadowLightShape shadowLightShape(const Light& light, const Vec3d& lightOrigin);

}  // namespace fp
