#pragma once
// Shadow-ray directions towards one light, as Unreal's ray-traced shadow generators choose them
// (reference §9.2): a concentric-disk sample of the directional light's cone (SourceRadius =
// sin(½·LightSourceAngle)), a uniform sample of the solid angle of a sphere light, a uniform point
// of a rect light. Positions are relative to the RayScene origin (camera-relative).
#include "passes/core/Math.h"
#include "passes/core/Scene.h"

namespace fp {

struct ShadowDirection {
    Vec3f dir;        //!< unit direction of the shadow ray
    float tfar = 0;   //!< where the ray stops: the light's surface, or far away for directional
};

class ShadowRayGenerator {
public:
    /// `lightOrigin`: the scene origin of the RayScene the rays go into (positions are relative).
    ShadowRayGenerator(const Light& light, const Vec3d& lightOrigin);

    /// False when the light sends nothing to `p`: beyond its attenuation radius, outside a spot's
    /// cone, behind a rect light (reference §9.2, "local lights: rays longer than the attenuation
    /// radius are skipped"). Such pixels are skipped.
    bool reaches(const Vec3f& p) const;
    /// Unit direction from `p` to the light's centre, the L of N·L culling and biasing.
    Vec3f centreDirection(const Vec3f& p) const;
    /// Ray towards the sample (u, v) ∈ [0,1)² of the light's extent, from the biased origin `o`.
    ShadowDirection sample(const Vec3f& o, float u, float v) const;

    const Light& light() const { return mLight; }

private:
    const Light& mLight;
    Vec3f mPosition;  // relative to the RayScene origin
    Vec3f mToLight;   // directional: unit vector towards the light
    Vec3f mAxis;      // spot axis (direction of travel), rect emission normal
    Vec3f mHalfU, mHalfV;
    float mCosOuter = -1.0f;
    float mSourceRadius = 0.0f;  // directional: sin(½ angle)
};

}  // namespace fp
