#include "passes/metrics/Heatmap.h"

#include "passes/core/Tiles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace fp {

namespace {

// Viridis sampled at 11 evenly spaced points (display-referred sRGB values).
constexpr std::array<std::array<float, 3>, 11> kViridis = {{
    {0.267f, 0.005f, 0.329f}, {0.283f, 0.141f, 0.458f}, {0.254f, 0.265f, 0.530f},
    {0.207f, 0.372f, 0.553f}, {0.164f, 0.471f, 0.558f}, {0.128f, 0.567f, 0.551f},
    {0.135f, 0.659f, 0.518f}, {0.267f, 0.749f, 0.441f}, {0.478f, 0.821f, 0.318f},
    {0.741f, 0.873f, 0.150f}, {0.993f, 0.906f, 0.144f},
}};

// sRGB electro-optical transfer function: display code value → linear.
float srgbToLinear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace

float heatScale(const Image& absError, const Image* mask) {
    std::vector<float> v;
    for (int y = 0; y < absError.height(); ++y)
        for (int x = 0; x < absError.width(); ++x)
            if (!mask || mask->plane(0).at(x, y) > 0.0f) v.push_back(absError.plane(0).at(x, y));
    if (v.empty()) return 0.0f;
    auto it = v.begin() + std::min(v.size() - 1, std::size_t(0.99 * double(v.size())));
    std::nth_element(v.begin(), it, v.end());
    return *it;
}

Image heatmap(const Image& absError, const Image* mask, float scale) {
    Image out(absError.width(), absError.height(), {"R", "G", "B"});
    const float grey = srgbToLinear(0.5f);
    forEachTile(out.width(), out.height(), [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (mask && !(mask->plane(0).at(x, y) > 0.0f)) {
                    for (int c = 0; c < 3; ++c) out.plane(c).at(x, y) = grey;
                    continue;
                }
                const float e = absError.plane(0).at(x, y);
                const float u = scale > 0.0f && std::isfinite(e) ? std::clamp(e / scale, 0.0f, 1.0f)
                                                                 : (e > 0.0f ? 1.0f : 0.0f);
                const float f = u * float(kViridis.size() - 1);
                const int i = std::min(int(f), int(kViridis.size()) - 2);
                const float w = f - float(i);
                for (int c = 0; c < 3; ++c)
                    out.plane(c).at(x, y) =
                        srgbToLinear(kViridis[i][c] * (1.0f - w) + kViridis[i + 1][c] * w);
            }
    });
    return out;
}

Image heatmapRamp(int steps) {
    Image ramp(steps, 1, {"Y"});
    for (int x = 0; x < steps; ++x)
        ramp.plane(0).at(x, 0) = steps > 1 ? float(x) / float(steps - 1) : 0.0f;
    return heatmap(ramp, nullptr, 1.0f);
}

std::vector<std::array<float, 3>> heatColorStops() {
    return {kViridis.begin(), kViridis.end()};
}

}  // namespace fp
