#pragma once
// Unreal's shading-model ids (algorithms §1.6), as the capture's ShadingModel buffer holds them.
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"

#include <cmath>

namespace fp {

enum ShadingModelId {
    kUnlit = 0, kDefaultLit, kSubsurface, kPreintegratedSkin, kClearCoat, kSubsurfaceProfile,
    kTwoSidedFoliage, kHair, kCloth, kEye
};

/// A pixel with a surface that takes lighting: finite positive depth (not sky) and not unlit, from
/// the shading model's id; D: a depth (double, or float lanes: LaneFloat.h), I: the id (int, or
/// int lanes), each lane on its own.
template <class D, class I>
FP_HD inline auto isLitSurfaceOf(D depth, I model) {
    return (depth > 0.0f) & !isInfOf(depth) & !(model == kUnlit);
}
/// The same from the ShadingModel buffer's value.
FP_HD inline bool isLitSurface(double depth, float shadingModel) {
    return isLitSurfaceOf(depth, truncToInt(shadingModel, 0, 255));
}

}  // namespace fp
