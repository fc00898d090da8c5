#include "shading/PreintegratedSkinLut.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace fp {

namespace {

struct SkinGaussian {
    double variance;  // mm²
    double red, green, blue;
};

// Skin diffusion profile R(d) = Σ wᵢ·G(vᵢ, d), G(v, d) = exp(−d²/(2v))/(2πv): d'Eon & Luebke's
// six-Gaussian fit of a three-layer skin model (GPU Gems 3, ch. 14 "Advanced Techniques for
// Realistic Real-Time Skin Rendering", the sum-of-Gaussians table), as published to our
// knowledge. Each channel's weights sum to 1; red keeps weight on the wide Gaussians, which is
// why skin bleeds red.
constexpr std::array<SkinGaussian, 6> kSkinProfile{{
    {0.0064, 0.233, 0.455, 0.649},
    {0.0484, 0.100, 0.336, 0.344},
    {0.187, 0.118, 0.198, 0.0},
    {0.567, 0.113, 0.007, 0.007},
    {1.99, 0.358, 0.004, 0.0},
    {7.41, 0.078, 0.0, 0.0},
}};

// Quadrature points per Gaussian. Each Gaussian is integrated on its own x range (out to a chord
// of 6σ, beyond which it is below e^−18 of its peak), so even the narrowest one (σ = 0.08 mm on a
// 2 mm sphere, 0.04 rad) gets ~20 points per σ and the table is free of quadrature ripple.
constexpr int kSteps = 256;

// One Gaussian of the profile laid out on the great circle of a sphere of radius r: midpoint
// nodes x and weights G(2r·sin(x/2))·dx.
struct RingKernel {
    std::array<double, kSteps> cosX, sinX, weight;
    double total = 0.0;
};

RingKernel ringKernel(double variance, double radius) {
    RingKernel k;
    const double sigma = std::sqrt(variance);
    const double reach = 3.0 * sigma / radius;  // chord 6σ ⇔ sin(x/2) = 3σ/r
    const double halfRange = reach >= 1.0 ? kPi : 2.0 * std::asin(reach);
    const double dx = 2.0 * halfRange / kSteps;
    for (int i = 0; i < kSteps; ++i) {
        const double x = -halfRange + (i + 0.5) * dx;
        const double d = 2.0 * radius * std::sin(0.5 * x);
        k.cosX[i] = std::cos(x);
        k.sinX[i] = std::sin(x);
        k.weight[i] = std::exp(-d * d / (2.0 * variance)) / (2.0 * kPi * variance) * dx;
        k.total += k.weight[i];
    }
    return k;
}

// ∫ saturate(cos(θ + x)) G dx for one Gaussian's kernel.
double blurredLambert(const RingKernel& k, double cosTheta, double sinTheta) {
    double s = 0.0;
    for (int i = 0; i < kSteps; ++i)
        s += k.weight[i] * std::max(cosTheta * k.cosX[i] - sinTheta * k.sinX[i], 0.0);
    return s;
}

}  // namespace

PreintegratedSkinLut::PreintegratedSkinLut() : mTexels(size_t(kSize) * kSize) {
    // Row v = 0 is a flat surface: D equals Lambert exactly, the table stays 0.
    for (int j = 1; j < kSize; ++j) {
        const double curvature = double(j) / (kSize - 1) / kMinRadiusMm;
        const double radius = 1.0 / curvature;
        std::array<RingKernel, kSkinProfile.size()> kernels;
        for (size_t g = 0; g < kSkinProfile.size(); ++g)
            kernels[g] = ringKernel(kSkinProfile[g].variance, radius);
        for (int i = 0; i < kSize; ++i) {
            const double cosTheta = 2.0 * i / (kSize - 1) - 1.0;
            const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
            // Numerator and denominator are sums over Gaussians, so each channel's D is a ratio
            // of weighted sums, not a weighted sum of per-Gaussian ratios.
            double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
            for (size_t g = 0; g < kSkinProfile.size(); ++g) {
                const double lit = blurredLambert(kernels[g], cosTheta, sinTheta);
                const double w[3] = {kSkinProfile[g].red, kSkinProfile[g].green,
                                     kSkinProfile[g].blue};
                for (int c = 0; c < 3; ++c) {
                    num[c] += w[c] * lit;
                    den[c] += w[c] * kernels[g].total;
                }
            }
            const double lambert = std::max(cosTheta, 0.0);
            float out[3];
            for (int c = 0; c < 3; ++c)
                out[c] = float(std::max(num[c] / den[c] - lambert, 0.0));
            mTexels[size_t(j) * kSize + i] = {out[0], out[1], out[2]};
        }
    }
}

const PreintegratedSkinLut& PreintegratedSkinLut::instance() {
    static const PreintegratedSkinLut lut;
    return lut;
}

}  // namespace fp
