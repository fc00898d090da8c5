#pragma once
// Reflection captures in the reflection composite (algorithms §8.3): which captures a point is
// in, the parallax-corrected lookup into each one's cubemap (against its sphere or box), the
// distance fade at its edge, and Unreal's front-to-back "under" compositing in ascending radius,
// each capture taking what the ones before it left of the reflection's weight.
#include "foundation/Math.h"
#include "shading/Cubemap.h"

#include <vector>

namespace fp {

/// A capture ready for one frame: its geometry relative to the eye and its prefiltered cubemap.
struct PreparedCapture {
    bool box = false;
    Vec3f centre;            //!< relative to the eye
    float radius = 0;        //!< influence radius (box: |extent|)
    Vec3f extent;            //!< box half size
    float transition = 0;    //!< box fade band
    float brightness = 1;
    Vec3f offset;            //!< CaptureOffset
    const Cubemap* cube = nullptr;
};

/// Where a point's reflection reads a capture.
struct CaptureLookup {
    bool inside = false;     //!< within the capture's influence
    Vec3f direction;         //!< the parallax-corrected lookup vector
    float distanceAlpha = 0;  //!< the fade towards the influence's edge
};

/// Sphere parallax: the ray p + t·R from p = P − C (inside the sphere of radius r) meets the
/// sphere at the far root t = √(b² − c) − b, b = R·p, c = |p|² − r²; lookup = p + t·R − offset;
/// alpha = 1 − smoothstep(0, 1, saturate(2.5·|p|/r − 1.5)): full inside 60 % of the radius.
CaptureLookup sphereParallax(const Vec3f& p, const Vec3f& R, float radius, const Vec3f& offset);

/// Box parallax (axis-aligned box of half size `extent`): the nearest of the far slab hits of
/// p + t·R in the box's [−1, 1]³ frame; lookup = p + t·R − offset; alpha = 1 − smoothstep(0,
/// 0.7·T, d), d the Manhattan distance of p outside the box shrunk by T/2. Inside = within the
/// bounding sphere |p| < |extent| (the alpha fades the rest).
CaptureLookup boxParallax(const Vec3f& p, const Vec3f& R, const Vec3f& extent, float transition,
                          const Vec3f& offset);

/// The captures' reflection for a point at `position` (relative to the eye) reflecting along
/// unit R at `roughness`, composited under each other in the order given while more than 0.001
/// of `alpha` is left; `alpha` comes back as what the sky may still fill.
Vec3f compositeCaptures(const std::vector<PreparedCapture>& captures, const Vec3f& position,
                        const Vec3f& R, float roughness, float& alpha);

}  // namespace fp
