#pragma once
// Noisy signals for the denoiser tests: a constant with uniform noise, fed to a chain as capture
// layers, and the statistics of a plane's central window (away from the borders, where a kernel
// loses its taps).
#include "foundation/Image.h"

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace fp::test {

/// `channels` planes of 0.5 + uniform noise in ±0.25 (variance 1/48) per pixel.
inline Image noisyConstant(int w, int h, std::vector<std::string> channels, std::mt19937& rng) {
    std::uniform_real_distribution<float> noise(0.25f, 0.75f);
    Image image(w, h, channels);
    for (int c = 0; c < image.channelCount(); ++c)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) image.plane(c).at(x, y) = noise(rng);
    return image;
}

struct WindowStats {
    double mean = 0, variance = 0;
    int count = 0;
};

/// Mean and variance of `p` over the pixels at least `border` from every edge.
inline WindowStats windowStats(const Plane& p, int border) {
    double s1 = 0, s2 = 0;
    int n = 0;
    for (int y = border; y < p.height() - border; ++y)
        for (int x = border; x < p.width() - border; ++x) {
            s1 += p.at(x, y);
            s2 += double(p.at(x, y)) * p.at(x, y);
            ++n;
        }
    const double mean = s1 / n;
    return {mean, s2 / n - mean * mean, n};
}

}  // namespace fp::test
