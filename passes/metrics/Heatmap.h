#pragma once
// Error heat maps a person can read: |error| through a perceptually uniform colour map (viridis:
// dark blue = 0, yellow = the scale's top), pixels outside the mask in neutral grey. The colours
// are stored scene-linear, so the display transform (sRGB) shows exactly the colour map.
#include "passes/core/Image.h"

#include <array>
#include <vector>

namespace fp {

/// The 99th percentile of the masked values of a 1-channel image (robust to a few fireflies);
/// 0 when nothing is masked in.
float heatScale(const Image& absError, const Image* mask);

/// RGB heat map of `absError` (1 channel) with `scale` mapped to the top of the colour map.
Image heatmap(const Image& absError, const Image* mask, float scale);

/// The colour map itself, `steps` × 1 pixels from 0 (left) to the top of the scale (right),
/// coloured as heatmap() colours them (scene-linear): the colour bar printed beside a heat map.
Image heatmapRamp(int steps = 256);

/// The colour map's display-referred sRGB stops, evenly spaced from 0 to the top (for an HTML
/// gradient that shows the same colours).
std::vector<std::array<float, 3>> heatColorStops();

}  // namespace fp
