#pragma once
// Where Unreal's ray-traced passes start a ray from a pixel's surface (ApplyCameraRelativeDepthBias,
// algorithms §9.2): towards the camera by max(1e-4·distance, bias), then along the normal by a bias
// that runs from `maxBias` (a ray grazing the surface, N·L = 0) down to `minBias` (a ray along
// the normal); `backSide` pushes into the surface instead (a transmissive pixel lit from behind).
#include "foundation/Camera.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

namespace fp {

/// The bias along a ray along the normal, and r.RayTracing.NormalBias's floor: 0.01 cm
/// (algorithms §9.1).
inline constexpr float kMinNormalBiasCm = 0.01f;

/// A pass's biases in scene units from its normal bias in cm (floored at 0.01 cm) and the scene's
/// units per cm: `max` at N·L = 0, `min` along the normal.
struct RayBias {
    float max, min;
    static RayBias fromCm(float normalBiasCm, float unitsPerCm) {
        return {(normalBiasCm > kMinNormalBiasCm ? normalBiasCm : kMinNormalBiasCm) * unitsPerCm,
                kMinNormalBiasCm * unitsPerCm};
    }
};

/// T: float, or float lanes (LaneFloat.h) with a mask of back sides.
template <class T>
FP_HD inline Vec3T<T> biasedRayOrigin(const Vec3T<T>& p, const Vec3T<T>& toEye, T eyeDistance,
                                      const Vec3T<T>& n, T NoL, float maxBias, float minBias,
                                      MaskOf<T> backSide = MaskOf<T>()) {
    const T eyeBias = 1e-4f * eyeDistance;
    Vec3T<T> o = p + toEye * maxLike(eyeBias, T(maxBias));
    const T nb = maxBias + (minBias - maxBias) * saturateOf(NoL);
    o += n * ifThenElse(backSide, -nb, nb);
    return o;
}

/// A pixel's surface as a ray-traced pass starts from it, rebuilt from its linear depth in double:
/// its position relative to the ray scene's origin (`eyeOffset`: the eye relative to that
/// origin), the unit vector to the eye and the distance to it.
template <class T>
struct PixelSurfaceOf {
    Vec3T<T> p, toEye;
    T eyeDistance;
};
using PixelSurface = PixelSurfaceOf<float>;
/// The same from the surface's offset from the eye (cam.translatedFromPixel, or
/// translatedFromPixelOf in double lanes: then a surface of float lanes), where the caller has it
/// already.
template <class D>
FP_HD inline auto pixelSurfaceAt(const Vec3d& eyeOffset, const Vec3T<D>& offset) {
    using T = decltype(toFloat(D{}));
    const D eyeDistance = length(offset);
    const Vec3T<D> at = Vec3T<D>(eyeOffset) + offset;
    return PixelSurfaceOf<T>{{toFloat(at.x), toFloat(at.y), toFloat(at.z)},
                             {toFloat(-offset.x / eyeDistance), toFloat(-offset.y / eyeDistance),
                              toFloat(-offset.z / eyeDistance)},
                             toFloat(eyeDistance)};
}
FP_HD inline PixelSurface pixelSurface(const CameraView& cam, const Vec3d& eyeOffset, int x, int y,
                                       double depth) {
    return pixelSurfaceAt(eyeOffset, cam.translatedFromPixel(x, y, depth));
}

/// biasedRayOrigin from a pixel's surface, with a pass's biases.
FP_HD inline Vec3f biasedRayOrigin(const PixelSurface& s, const Vec3f& n, float NoL,
                                   const RayBias& bias) {
    return biasedRayOrigin(s.p, s.toEye, s.eyeDistance, n, NoL, bias.max, bias.min);
}

}  // namespace fp
