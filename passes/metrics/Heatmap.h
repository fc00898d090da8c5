#pragma once
// Error heat maps a person can read: |error| through a perceptually uniform colour map (viridis:
// dark blue = 0, yellow = the scale's top), pixels outside the mask in neutral grey. The colours
// are stored scene-linear, so the display transform (sRGB) shows exactly the colour map.
#include "passes/core/Image.h"

namespace fp {

/// The 99th percentile of the masked values of a 1-channel image (robust to a few fireflies);
/// 0 when nothing is masked in.
float heatScale(const Image& absError, const Image* mask);

/// RGB heat map of `absError` (1 channel) with `scale` mapped to the top of the colour map.
Image heatmap(const Image& absError, const Image* mask, float scale);

}  // namespace fp
