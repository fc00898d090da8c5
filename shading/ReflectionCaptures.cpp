#include "shading/ReflectionCaptures.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp {

namespace {

float smoothstep(float a, float b, float x) {
    const float t = b > a ? saturate((x - a) / (b - a)) : (x >= b ? 1.0f : 0.0f);
    return t * t * (3.0f - 2.0f * t);
}

}  // namespace

CaptureLookup sphereParallax(const Vec3f& p, const Vec3f& R, float radius, const Vec3f& offset) {
    CaptureLookup out;
    const float c = dot(p, p) - radius * radius;
    if (!(c < 0.0f)) return out;
    const float b = dot(R, p);
    const float t = std::sqrt(std::max(b * b - c, 0.0f)) - b;
    out.inside = true;
    out.direction = p + R * t - offset;
    const float normalisedDistance = std::sqrt(dot(p, p)) / radius;
    out.distanceAlpha = 1.0f - smoothstep(0.0f, 1.0f, saturate(2.5f * normalisedDistance - 1.5f));
    return out;
}

CaptureLookup boxParallax(const Vec3f& p, const Vec3f& R, const Vec3f& extent, float transition,
                          const Vec3f& offset) {
    CaptureLookup out;
    if (!(dot(p, p) < dot(extent, extent))) return out;
    float t = std::numeric_limits<float>::infinity();
    float outside = 0.0f;
    for (int a = 0; a < 3; ++a) {
        const float l = p[a] / extent[a], r = R[a] / extent[a];
        if (r != 0.0f) t = std::min(t, std::max((1.0f - l) / r, (-1.0f - l) / r));
        outside += std::max(std::fabs(p[a]) - std::max(extent[a] - 0.5f * transition, 0.0f), 0.0f);
    }
    if (!std::isfinite(t)) return out;
    out.inside = true;
    out.direction = p + R * t - offset;
    out.distanceAlpha = 1.0f - smoothstep(0.0f, 0.7f * transition, outside);
    return out;
}

Vec3f compositeCaptures(const std::vector<PreparedCapture>& captures, const Vec3f& position,
                        const Vec3f& R, float roughness, float& alpha) {
    Vec3f color;
    for (const PreparedCapture& c : captures) {
        if (alpha <= 0.001f) break;
        const Vec3f p = position - c.centre;
        const CaptureLookup look = c.box ? boxParallax(p, R, c.extent, c.transition, c.offset)
                                         : sphereParallax(p, R, c.radius, c.offset);
        if (!look.inside || look.distanceAlpha <= 0.0f) continue;
        const Vec3f sample = c.cube->sample(look.direction, c.cube->mipForRoughness(roughness)) *
                             (c.brightness * look.distanceAlpha);
        color += sample * alpha;
        alpha *= 1.0f - look.distanceAlpha;  // the capture's alpha is 1: opaque where it fades in
    }
    return color;
}

}  // namespace fp
