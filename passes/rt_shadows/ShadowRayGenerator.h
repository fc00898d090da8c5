#pragma once
// Shadow-ray directions towards one light, as Unreal's ray-traced shadow generators choose them
// (algorithms §9.2): a concentric-disk sample of the directional light's cone (SourceRadius =
// sin(½·LightSourceAngle)), a uniform sample of the solid angle of a sphere light, a uniform point
// of a rect light. Positions are relative to the RayScene origin (camera-relative).
#include "foundation/Math.h"
#include "foundation/Scene.h"

namespace fp {

struct ShadowDirection {
    Vec3f dir;        //!< unit direction of the shadow ray
    float tfar = 0;   //!< where the ray stops: the light's surface, or far away for directional
};

/// The light as its shadow rays see it, in the float terms both the scalar generator below and
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

class ShadowRayGenerator {
public:
    /// `lightOrigin`: the scene origin of the RayScene the rays go into (positions are relative).
    ShadowRayGenerator(const Light& light, const Vec3d& lightOrigin);

    /// False when the light sends nothing to `p`: beyond its attenuation radius, outside a spot's
    /// cone, behind a rect light (algorithms §9.2, "local lights: rays longer than the attenuation
    /// radius are skipped"). Such pixels are skipped.
    bool reaches(const Vec3f& p) const;
    /// Unit direction from `p` to the light's centre, the L of N·L culling and biasing.
    Vec3f centreDirection(const Vec3f& p) const;
    /// Ray towards the sample (u, v) ∈ [0,1)² of the light's extent, from the biased origin `o`.
    ShadowDirection sample(const Vec3f& o, float u, float v) const;

    const Light& light() const { return mLight; }
    const ShadowLightShape& shape() const { return mShape; }

private:
    const Light& mLight;
    ShadowLightShape mShape;
};

}  // namespace fp
