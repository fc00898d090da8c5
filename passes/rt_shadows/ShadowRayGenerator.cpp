#include "passes/rt_shadows/ShadowRayGenerator.h"

#include "foundation/Sampling.h"
#include "foundation/SinCos.h"
#include "foundation/UnrealRandom.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp {

ShadowRayGenerator::ShadowRayGenerator(const Light& light, const Vec3d& lightOrigin)
    : mLight(light) {
    ShadowLightShape& s = mShape;
    s.type = light.type;
    s.position = Vec3f(light.position - lightOrigin);
    s.toLight = normalize(-Vec3f(light.direction));
    orthonormalBasis(s.toLight, s.toLightT, s.toLightB);
    s.axis = normalize(Vec3f(light.direction));
    s.halfU = Vec3f(light.halfU);
    s.halfV = Vec3f(light.halfV);
    if (light.type == LightType::Rect) s.axis = normalize(cross(s.halfU, s.halfV));
    if (light.type == LightType::Spot) s.cosOuter = std::cos(light.outerConeDegrees * kPiF / 180.0f);
    s.sourceRadius = std::sin(0.5f * light.sourceAngleDegrees * kPiF / 180.0f);
    s.radius = light.radius;
    s.reachBound = std::numeric_limits<float>::infinity();
    if (light.type != LightType::Directional && light.attenuationRadius > 0.0) {
        float bound = float(light.attenuationRadius);
        if (double(bound) > light.attenuationRadius)
            bound = std::nextafter(bound, -std::numeric_limits<float>::infinity());
        s.reachBound = bound;
    }
}

bool ShadowRayGenerator::reaches(const Vec3f& p) const {
    const ShadowLightShape& s = mShape;
    if (s.type == LightType::Directional) return true;
    const Vec3f d = s.position - p;
    if (length(d) > s.reachBound) return false;
    if (s.type == LightType::Spot) return dot(normalize(-d), s.axis) > s.cosOuter;
    if (s.type == LightType::Rect) return dot(-d, s.axis) > 0.0f;
    return true;
}

Vec3f ShadowRayGenerator::centreDirection(const Vec3f& p) const {
    if (mShape.type == LightType::Directional) return mShape.toLight;
    return normalize(mShape.position - p);
}

ShadowDirection ShadowRayGenerator::sample(const Vec3f& o, float u, float v) const {
    const ShadowLightShape& l = mShape;
    ShadowDirection s;
    switch (l.type) {
    case LightType::Directional: {
        float dx, dy;
        ue::concentricDisk(u, v, dx, dy);
        s.dir = normalize(l.toLight + (l.toLightT * dx + l.toLightB * dy) * l.sourceRadius);
        s.tfar = ShadowLightShape::kDirectionalTraceDistance;
        return s;
    }
    case LightType::Rect: {
        const Vec3f q = l.position + l.halfU * (2.0f * u - 1.0f) + l.halfV * (2.0f * v - 1.0f);
        const Vec3f d = q - o;
        const float dist = length(d);
        s.dir = d / dist;
        // Stop just short of the emitter: its own quad, when it is in the geometry, is no occluder.
        s.tfar = dist * (1.0f - 1e-4f);
        return s;
    }
    case LightType::Point:
    case LightType::Spot: {
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
        const float sinMax = r / dist, cosMax = std::sqrt(std::max(0.0f, 1.0f - sinMax * sinMax));
        const float cosT = 1.0f - u * (1.0f - cosMax);
        const float sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
        float sinPhi, cosPhi;
        sinCos(2.0f * kPiF * v, sinPhi, cosPhi);
        Vec3f t, b;
        orthonormalBasis(L, t, b);
        s.dir = normalize(t * (sinT * cosPhi) + b * (sinT * sinPhi) + L * cosT);
        // Distance to the near side of the sphere along the ray.
        const float along = dist * cosT;
        s.tfar = std::max(0.0f, along - std::sqrt(std::max(0.0f, r * r - dist * dist * sinT * sinT)));
        return s;
    }
    }
    return s;
}

}  // namespace fp
