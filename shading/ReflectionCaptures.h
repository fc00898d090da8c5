#pragma once
// Reflection captures in the reflection composite (algorithms §8.3): which captures a point is
// in, the parallax-corrected lookup into each one's cubemap (against its sphere or box), the
// distance fade at its edge, and Unreal's front-to-back "under" compositing in ascending radius,
// each capture taking what the ones before it left of the reflection's weight.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "shading/Cubemap.h"

#include <cmath>
#include <limits>

namespace fp {

/// A capture ready for one frame: its geometry relative to the eye and its prefiltered cubemap
/// (a view of the host's or, on the GPU, of a device copy).
struct PreparedCapture {
    bool box = false;
    Vec3f centre;            //!< relative to the eye
    float radius = 0;        //!< influence radius (box: |extent|)
    Vec3f extent;            //!< box half size
    float transition = 0;    //!< box fade band
    float brightness = 1;
    Vec3f offset;            //!< CaptureOffset
    CubemapView cube;
};

/// Where a point's reflection reads a capture.
struct CaptureLookup {
    bool inside = false;     //!< within the capture's influence
    Vec3f direction;         //!< the parallax-corrected lookup vector
    float distanceAlpha = 0;  //!< the fade towards the influence's edge
};

FP_HD inline float smoothstep(float a, float b, float x) {
    const float t = b > a ? saturate((x - a) / (b - a)) : (x >= b ? 1.0f : 0.0f);
    return t * t * (3.0f - 2.0f * t);
}

/// Sphere parallax: the ray p + t·R from p = P − C (inside the sphere of radius r) meets the
/// sphere at the far root t = √(b² − c) − b, b = R·p, c = |p|² − r²; lookup = p + t·R − offset;
/// alpha = 1 − smoothstep(0, 1, saturate(2.5·|p|/r − 1.5)): full inside 60 % of the radius.
FP_HD inline CaptureLookup sphereParallax(const Vec3f& p, const Vec3f& R, float radius, const Vec3f& offset) {
    CaptureLookup out;
    const float c = dot(p, p) - radius * radius;
    if (!(c < 0.0f)) return out;
    const float b = dot(R, p);
    const float root = b * b - c;
    const float t = std::sqrt(root > 0.0f ? root : 0.0f) - b;
    out.inside = true;
    out.direction = p + R * t - offset;
    const float normalisedDistance = std::sqrt(dot(p, p)) / radius;
    out.distanceAlpha = 1.0f - smoothstep(0.0f, 1.0f, saturate(2.5f * normalisedDistance - 1.5f));
    return out;
}

/// Box parallax (axis-aligned box of half size `extent`): the nearest of the far slab hits of
/// p + t·R in the box's [−1, 1]³ frame; lookup = p + t·R − offset; alpha = 1 − smoothstep(0,
/// 0.7·T, d), d the Manhattan distance of p outside the box shrunk by T/2. Inside = within the
/// bounding sphere |p| < |extent| (the alpha fades the rest).
FP_HD inline CaptureLookup boxParallax(const Vec3f& p, const Vec3f& R, const Vec3f& extent, float transition,
                                       const Vec3f& offset) {
    CaptureLookup out;
    if (!(dot(p, p) < dot(extent, extent))) return out;
    float t = std::numeric_limits<float>::infinity();
    float outside = 0.0f;
    for (int a = 0; a < 3; ++a) {
        const float l = p[a] / extent[a], r = R[a] / extent[a];
        if (r != 0.0f) {
            const float near = (1.0f - l) / r, far = (-1.0f - l) / r;
            const float exit = near > far ? near : far;
            t = exit < t ? exit : t;
        }
        const float shrunk = extent[a] - 0.5f * transition;
        const float beyond = std::fabs(p[a]) - (shrunk > 0.0f ? shrunk : 0.0f);
        outside += beyond > 0.0f ? beyond : 0.0f;
    }
    if (!std::isfinite(t)) return out;
    out.inside = true;
    out.direction = p + R * t - offset;
    out.distanceAlpha = 1.0f - smoothstep(0.0f, 0.7f * transition, outside);
    return out;
}

/// The captures' reflection for a point at `position` (relative to the eye) reflecting along
/// unit R at `roughness`, composited under each other in the order given while more than 0.001
/// of `alpha` is left; `alpha` comes back as what the sky may still fill.
FP_HD inline Vec3f compositeCaptures(const PreparedCapture* captures, int count, const Vec3f& position,
                                     const Vec3f& R, float roughness, float& alpha) {
    Vec3f color;
    for (int i = 0; i < count; ++i) {
        const PreparedCapture& c = captures[i];
        if (alpha <= 0.001f) break;
        const Vec3f p = position - c.centre;
        const CaptureLookup look = c.box ? boxParallax(p, R, c.extent, c.transition, c.offset)
                                         : sphereParallax(p, R, c.radius, c.offset);
        if (!look.inside || look.distanceAlpha <= 0.0f) continue;
        const Vec3f sample = c.cube.sample(look.direction, c.cube.mipForRoughness(roughness)) *
                             (c.brightness * look.distanceAlpha);
        color += sample * alpha;
        alpha *= 1.0f - look.distanceAlpha;  // the capture's alpha is 1: opaque where it fades in
    }
    return color;
}

}  // namespace fp
