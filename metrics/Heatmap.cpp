#include "metrics/Heatmap.h"

#include "foundation/Tiles.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace fp {

float heatScale(const Image& absError, const Image* mask) {
    std::vector<float> v;
    for (int y = 0; y < absError.height(); ++y)
        for (int x = 0; x < absError.width(); ++x)
            // A non-finite pixel (drawn at the top of the map) does not set the scale.
            if ((!mask || mask->plane(0).at(x, y) > 0.0f) && std::isfinite(absError.plane(0).at(x, y)))
                v.push_back(absError.plane(0).at(x, y));
    if (v.empty()) return 0.0f;
    auto it = v.begin() + std::min(v.size() - 1, std::size_t(0.99 * double(v.size())));
    std::nth_element(v.begin(), it, v.end());
    return *it;
}

Image heatmap(const Image& absError, const Image* mask, float scale) {
    Image out(absError.width(), absError.height(), {"R", "G", "B"});
    const float grey = heatMaskedGrey();
    const PlaneView error = viewOf(absError.plane(0));
    const PlaneView inside = mask ? viewOf(mask->plane(0)) : PlaneView{};
    forEachTile(out.width(), out.height(), [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                float rgb[3];
                heatPixel(error, inside, scale, grey, x, y, rgb);
                for (int c = 0; c < 3; ++c)
                    out.plane(c).at(x, y) = rgb[c];
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
    std::vector<std::array<float, 3>> stops(kViridisStops);
    for (int i = 0; i < kViridisStops; ++i)
        stops[i] = {viridisStop(i, 0), viridisStop(i, 1), viridisStop(i, 2)};
    return stops;
}

}  // namespace fp
