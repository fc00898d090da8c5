#pragma once
// Order-3 (9-coefficient) real spherical harmonics of RGB radiance, and the Lambert-convolved
// lookup Unreal's sky diffuse makes from them (algorithms §8.1: the packing folds the clamped-cosine
// convolution and 1/π in, so DiffuseColor × diffuse(N) is outgoing radiance). With the convolution
// factors A_l/π = 1, 2/3, 1/4 this is Ramamoorthi & Hanrahan's irradiance environment map;
// Unreal's constants c1 = √3/(3√π) = Y₁·(2/3) and c3 = √5/(16√π) = Y₂₀·(1/4) are these same
// products, spelled out.
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <algorithm>
#include <array>

namespace fp {

/// The nine real SH basis functions at unit direction d (l = 0, 1, 2; m = −l..l).
FP_HD inline std::array<float, 9> sh3Basis(const Vec3f& d) {
    return {0.282094792f,
            0.488602512f * d.y,
            0.488602512f * d.z,
            0.488602512f * d.x,
            1.092548431f * d.x * d.y,
            1.092548431f * d.y * d.z,
            0.315391565f * (3.0f * d.z * d.z - 1.0f),
            1.092548431f * d.x * d.z,
            0.546274215f * (d.x * d.x - d.y * d.y)};
}

struct SH3 {
    std::array<Vec3f, 9> coefficients{};

    /// Adds radiance `L` arriving from `d` over solid angle `weight` (∫ L·Y dω, one term).
    void add(const Vec3f& d, const Vec3f& L, float weight) {
        const std::array<float, 9> y = sh3Basis(d);
        for (int i = 0; i < 9; ++i) coefficients[size_t(i)] += L * (y[size_t(i)] * weight);
    }

    /// The projected radiance itself at d (band-limited to order 3).
    FP_HD Vec3f radiance(const Vec3f& d) const { return evaluate(d, {1.0f, 1.0f, 1.0f}); }

    /// Irradiance/π at a surface of unit normal n, clamped at 0 as Unreal's GetSkySHDiffuse.
    FP_HD Vec3f diffuse(const Vec3f& n) const {
        const Vec3f e = evaluate(n, {1.0f, 2.0f / 3.0f, 0.25f});
        return {e.x > 0.0f ? e.x : 0.0f, e.y > 0.0f ? e.y : 0.0f, e.z > 0.0f ? e.z : 0.0f};
    }

private:
    FP_HD Vec3f evaluate(const Vec3f& d, const std::array<float, 3>& band) const {
        const std::array<float, 9> y = sh3Basis(d);
        Vec3f s;
        for (int i = 0; i < 9; ++i) s += coefficients[size_t(i)] * (y[size_t(i)] * band[i == 0 ? 0 : i < 4 ? 1 : 2]);
        return s;
    }
};

}  // namespace fp
