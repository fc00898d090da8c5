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

/// A pixel with a surface that takes lighting: finite positive depth (not sky) and not unlit.
FP_HD inline bool isLitSurface(double depth, float shadingModel) {
    return depth > 0.0 && !std::isinf(depth) && truncToInt(shadingModel, 0, 255) != kUnlit;
}

}  // namespace fp
