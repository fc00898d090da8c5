#pragma once
// Error heat maps a person can read: |error| through a perceptually uniform colour map (viridis:
// dark blue = 0, yellow = the scale's top), pixels outside the mask in neutral grey. The colours
// are stored scene-linear, so the display transform (sRGB) shows exactly the colour map.
#include "foundation/HostDevice.h"
#include "foundation/Image.h"
#include "foundation/PlaneView.h"

#include <cmath>

#include <array>
#include <vector>

namespace fp {

/// sRGB electro-optical transfer function: display code value → linear.
FP_HD inline float srgbToLinear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

/// Grey, for pixels outside the mask (scene-linear).
FP_HD inline float heatMaskedGrey() {
    return srgbToLinear(0.5f);
}

inline constexpr int kViridisStops = 11;

/// Viridis sampled at 11 evenly spaced points (display-referred sRGB values): stop i, channel c.
FP_HD inline float viridisStop(int i, int c) {
    const float viridis[kViridisStops][3] = {
        {0.267f, 0.005f, 0.329f}, {0.283f, 0.141f, 0.458f}, {0.254f, 0.265f, 0.530f},
        {0.207f, 0.372f, 0.553f}, {0.164f, 0.471f, 0.558f}, {0.128f, 0.567f, 0.551f},
        {0.135f, 0.659f, 0.518f}, {0.267f, 0.749f, 0.441f}, {0.478f, 0.821f, 0.318f},
        {0.741f, 0.873f, 0.150f}, {0.993f, 0.906f, 0.144f},
    };
    return viridis[i][c];
}

/// The scene-linear colour of |error| `e` with `scale` at the top of the colour map.
FP_HD inline void heatColor(float e, float scale, float rgb[3]) {
    const float r = e / scale;
    const float u = scale > 0.0f && std::isfinite(e) ? (r < 0.0f ? 0.0f : (r > 1.0f ? 1.0f : r))
                                                     : (e > 0.0f ? 1.0f : 0.0f);
    const float f = u * float(kViridisStops - 1);
    const int i = int(f) < kViridisStops - 2 ? int(f) : kViridisStops - 2;
    const float w = f - float(i);
    for (int c = 0; c < 3; ++c)
        rgb[c] = srgbToLinear(viridisStop(i, c) * (1.0f - w) + viridisStop(i + 1, c) * w);
}

/// The heat-map colour of pixel (x, y): its |error| through the colour map, or `grey`
/// (heatMaskedGrey()) outside the mask (null data: no mask). Both backends write heat maps with it.
FP_HD inline void heatPixel(const PlaneView& absError, const PlaneView& mask, float scale,
                            float grey, int x, int y, float rgb[3]) {
    rgb[0] = rgb[1] = rgb[2] = grey;
    if (!mask.data || mask.at(x, y) > 0.0f)
        heatColor(absError.at(x, y), scale, rgb);
}

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
