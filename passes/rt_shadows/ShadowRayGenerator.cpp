#include "passes/rt_shadows/ShadowRayGenerator.h"

#include "passes/core/Sampling.h"
#include "passes/core/UnrealRandom.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {
// Reference §9.2: directional shadow rays run to 1e27, i.e. to infinity for any scene.
constexpr float kDirectionalTraceDistance = 1e27f;
}  // namespace

ShadowRayGenerator::ShadowRayGenerator(const Light& light, const Vec3d& lightOrigin)
    : mLight(light),
      mPosition(Vec3f(light.position - lightOrigin)),
      mToLight(normalize(-Vec3f(light.direction))),
      mAxis(normalize(Vec3f(light.direction))),
      mHalfU(Vec3f(light.halfU)),
      mHalfV(Vec3f(light.halfV)) {
    if (light.type == LightType::Rect) mAxis = normalize(cross(mHalfU, mHalfV));
    if (light.type == LightType::Spot) mCosOuter = std::cos(light.outerConeDegrees * kPiF / 180.0f);
    mSourceRadius = std::sin(0.5f * light.sourceAngleDegrees * kPiF / 180.0f);
}

bool ShadowRayGenerator::reaches(const Vec3f& p) const {
    if (mLight.type == LightType::Directional) return true;
    const Vec3f d = mPosition - p;
    if (mLight.attenuationRadius > 0.0 && length(d) > mLight.attenuationRadius) return false;
    if (mLight.type == LightType::Spot) return dot(normalize(-d), mAxis) > mCosOuter;
    if (mLight.type == LightType::Rect) return dot(-d, mAxis) > 0.0f;
    return true;
}

Vec3f ShadowRayGenerator::centreDirection(const Vec3f& p) const {
    if (mLight.type == LightType::Directional) return mToLight;
    return normalize(mPosition - p);
}

ShadowDirection ShadowRayGenerator::sample(const Vec3f& o, float u, float v) const {
    ShadowDirection s;
    switch (mLight.type) {
    case LightType::Directional: {
        float dx, dy;
        ue::concentricDisk(u, v, dx, dy);
        Vec3f t, b;
        orthonormalBasis(mToLight, t, b);
        s.dir = normalize(mToLight + (t * dx + b * dy) * mSourceRadius);
        s.tfar = kDirectionalTraceDistance;
        return s;
    }
    case LightType::Rect: {
        const Vec3f q = mPosition + mHalfU * (2.0f * u - 1.0f) + mHalfV * (2.0f * v - 1.0f);
        const Vec3f d = q - o;
        const float dist = length(d);
        s.dir = d / dist;
        // Stop just short of the emitter: its own quad, when it is in the geometry, is no occluder.
        s.tfar = dist * (1.0f - 1e-4f);
        return s;
    }
    case LightType::Point:
    case LightType::Spot: {
        const Vec3f d = mPosition - o;
        const float dist = length(d);
        const Vec3f L = d / dist;
        const float r = mLight.radius;
        if (r <= 0.0f || dist <= r) {  // a point, or a pixel inside the sphere
            s.dir = L;
            s.tfar = dist <= r ? 0.0f : dist;
            return s;
        }
        // Uniform in the solid angle the sphere subtends (reference §9.2, inferred generator).
        const float sinMax = r / dist, cosMax = std::sqrt(std::max(0.0f, 1.0f - sinMax * sinMax));
        const float cosT = 1.0f - u * (1.0f - cosMax);
        const float sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
        const float phi = 2.0f * kPiF * v;
        Vec3f t, b;
        orthonormalBasis(L, t, b);
        s.dir = normalize(t * (sinT * std::cos(phi)) + b * (sinT * std::sin(phi)) + L * cosT);
        // Distance to the near side of the sphere along the ray.
        const float along = dist * cosT;
        s.tfar = std::max(0.0f, along - std::sqrt(std::max(0.0f, r * r - dist * dist * sinT * sinT)));
        return s;
    }
    }
    return s;
}

}  // namespace fp
