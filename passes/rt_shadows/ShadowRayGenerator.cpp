#include "passes/rt_shadows/ShadowRayGenerator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp {

ShadowLightShape shadowLightShape(const Light& light, const Vec3d& lightOrigin) {
    ShadowLightShape s;
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
    return s;
}

}  // namespace fp
