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

struct ShadowDirection {
    Vec3f dir;        //!< unit direction of the shadow ray
    float tfar = 0;   //!< where the ray stops: the light's surface, or far away for directional
};

/// The light as its shadow rays see it, in the float terms both the scalar functions below and
/// the SIMD lanes (ShadowLanes.h) compute with.
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

/// False when the light sends nothing to `p`: beyond its attenuation radius, outside a spot's
/// cone, behind a rect light (algorithms §9.2, "local lights: rays longer than the attenuation
/// radius are skipped"). Such pixels are skipped.
FP_HD inline bool lightReaches(const ShadowLightShape& s, const Vec3f& p) {
    if (s.type == LightType::Directional) return true;
    const Vec3f d = s.position - p;
    if (length(d) > s.reachBound) return false;
    if (s.type == LightType::Spot) return dot(normalize(-d), s.axis) > s.cosOuter;
    if (s.type == LightType::Rect) return dot(-d, s.axis) > 0.0f;
    return true;
}

/// Unit direction from `p` to the light's centre, the L of N·L culling and biasing.
FP_HD inline Vec3f lightCentreDirection(const ShadowLightShape& s, const Vec3f& p) {
    if (s.type == LightType::Directional) return s.toLight;
    return normalize(s.position - p);
}

/// Ray towards the sample (u, v) ∈ [0,1)² of the light's extent, from the biased origin `o`.
FP_HD inline ShadowDirection sampleLight(const ShadowLightShape& l, const Vec3f& o, float u, float v) {
    ShadowDirection s;
    if (l.type == LightType::Directional) {
        float dx, dy;
        ue::concentricDisk(u, v, dx, dy);
        s.dir = normalize(l.toLight + (l.toLightT * dx + l.toLightB * dy) * l.sourceRadius);
        s.tfar = ShadowLightShape::kDirectionalTraceDistance;
        return s;
    }
    if (l.type == LightType::Rect) {
        const Vec3f q = l.position + l.halfU * (2.0f * u - 1.0f) + l.halfV * (2.0f * v - 1.0f);
        const Vec3f d = q - o;
        const float dist = length(d);
        s.dir = d / dist;
        // Stop just short of the emitter: its own quad, when it is in the geometry, is no occluder.
        s.tfar = dist * (1.0f - 1e-4f);
        return s;
    }
    // Point and spot lights.
    const Vec3f d = l.position - o;
    const float dist = length(d);
    const Vec3f L = d / dist;
    const float r = l.radius;
    if (r <= 0.0f || dist <= r) {  // a point, or a pixel inside the sphere
        s.dir = L;
        s.tfar = dist <= r ? 0.0f : dist;
        return s;
    }
    // Uniform in the solid angle the sphere subtends (algorithms §9.2, inferred generator).
    const float sinMax = r / dist, cosMaxSq = 1.0f - sinMax * sinMax;
    const float cosMax = std::sqrt(cosMaxSq > 0.0f ? cosMaxSq : 0.0f);
    const float cosT = 1.0f - u * (1.0f - cosMax);
    const float sinTSq = 1.0f - cosT * cosT;
    const float sinT = std::sqrt(sinTSq > 0.0f ? sinTSq : 0.0f);
    float sinPhi, cosPhi;
    sinCos(2.0f * kPiF * v, sinPhi, cosPhi);
    Vec3f t, b;
    orthonormalBasis(L, t, b);
    s.dir = normalize(t * (sinT * cosPhi) + b * (sinT * sinPhi) + L * cosT);
    // Distance to the near side of the sphere along the ray.
    const float along = dist * cosT;
    const float chordSq = r * r - dist * dist * sinT * sinT;
    const float near = along - std::sqrt(chordSq > 0.0f ? chordSq : 0.0f);
    s.tfar = near > 0.0f ? near : 0.0f;
    return s;
}

/// The light as its shadow rays see it, around `lightOrigin`: the scene origin of the RayScene the
/// rays go into (positions are relative).
ShadowLightShape shadowLightShape(const Light& light, const Vec3d& lightOrigin);

}  // namespace fp
