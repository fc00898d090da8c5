#pragma once
// A cubemap of RGB radiance with a mip chain, as Unreal keeps its sky light and its reflection
// captures (algorithms §8.3): mip 0 is the radiance itself, each further mip is prefiltered with the
// GGX lobe of the roughness that maps to it, so one trilinear fetch at the roughness's mip gives
// the prefiltered radiance of the split-sum approximation. Shared by the sky light and (later)
// the reflection captures, which framepass renders itself.
//
// Faces in OpenGL order (+X, −X, +Y, −Y, +Z, −Z) with OpenGL's face axes; texel centres at
// (i + 0.5)/size.
#include "foundation/Image.h"
#include "foundation/Math.h"
#include "shading/SphericalHarmonics.h"

#include <functional>
#include <vector>

namespace fp {

class Cubemap {
public:
    /// Renders `size`² texels a face from `radiance(direction)`, 2×2 samples a texel (so a finer
    /// source, a lat-long map, is averaged rather than point-sampled), then prefilters the mips.
    static Cubemap render(int size, const std::function<Vec3f(const Vec3f&)>& radiance);
    /// The same from faces already made: a strip of six `size`² faces stacked top to bottom
    /// (+X, −X, +Y, −Y, +Z, −Z), RGB, size a power of two.
    static Cubemap fromFaces(const Image& strip);
    /// The faces render() starts from, as such a strip.
    static Image renderFaces(int size, const std::function<Vec3f(const Vec3f&)>& radiance);

    int size() const { return mSize; }
    int mipCount() const { return int(mMips.size()); }

    /// Trilinear radiance in direction d (any length > 0) at fractional mip `mip` (clamped).
    Vec3f sample(const Vec3f& d, float mip) const;

    /// Unreal's ComputeReflectionCaptureMipFromRoughness: (log2(size) − 1) − (1 − 1.2·log2 r),
    /// with r floored at 0.001. Not clamped; sample() clamps.
    float mipForRoughness(float roughness) const;
    /// Its inverse: the GGX roughness a mip is prefiltered with (clamped to 1; mip 0 is mirror).
    float roughnessForMip(int mip) const;

    /// ∫ L·Y dω of mip 0 over the sphere, each texel weighted by its solid angle.
    SH3 projectSH() const;

    /// Unit direction through texel centre-relative face coordinates s, t ∈ [−1, 1].
    static Vec3f direction(int face, float s, float t);
    /// The solid angle of texel (x, y) of a face `size` texels wide.
    static double texelSolidAngle(int x, int y, int size);

    /// GGX samples per prefiltered texel (Hammersley; deterministic, so every run agrees).
    static constexpr int kPrefilterSamples = 64;

private:
    struct Mip {
        int size = 0;
        std::vector<Vec3f> texels;  // face-major, then rows of `size`
        Vec3f at(int face, int x, int y) const { return texels[(size_t(face) * size + size_t(y)) * size + size_t(x)]; }
    };
    static Vec3f bilinear(const Mip& m, const Vec3f& d);
    static std::vector<Mip> boxChain(Mip base);
    int mSize = 0;
    std::vector<Mip> mMips;
};

}  // namespace fp
