#pragma once
// The bilateral weight of Unreal's screen-space denoiser (algorithms §6.2 for SSGI, §6.3 for
// shadows): a neighbour counts as much as it lies on the receiver's tangent plane and faces the
// same way, so a blur neither crosses a crease nor reaches a surface in front of or behind it.
#include "screenspace/Surface.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <algorithm>
#include <cmath>

namespace fp {

/// W = saturate(1 − |N_ref·(P − P_ref)|/D) × max(N_ref·N, 0)⁴ for a neighbour at camera-relative
/// `position` with world `normal`, `distance` D the plane-distance tolerance (scene units).
FP_HD inline float bilateralWeight(const Surface& ref,
                             const Vec3f& position,
                             const Vec3f& normal,
                             float distance) {
    const float plane = std::fabs(dot(ref.normal, position - ref.position));
    const float wPos = saturate(1.0f - plane / distance);
    const float c = std::max(dot(ref.normal, normal), 0.0f);
    return wPos * (c * c) * (c * c);
}

FP_HD inline float bilateralWeight(const Surface& ref, const Surface& neighbour, float distance) {
    return bilateralWeight(ref, neighbour.position, neighbour.normal, distance);
}

}  // namespace fp
