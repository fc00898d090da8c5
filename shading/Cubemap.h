#pragma once
// A cubemap of RGB radiance with a mip chain, as Unreal keeps its sky light and its reflection
// captures (algorithms §8.3): mip 0 is the radiance itself, each further mip is prefiltered with the
// GGX lobe of the roughness that maps to it, so one trilinear fetch at the roughness's mip gives
// the prefiltered radiance of the split-sum approximation. Shared by the sky light and (later)
// the reflection captures, which framepass renders itself.
//
// Faces in OpenGL order (+X, −X, +Y, −Y, +Z, −Z) with OpenGL's face axes; texel centres at
// (i + 0.5)/size.
#include "foundation/ExpLog.h"
#include "foundation/HostDevice.h"
#include "foundation/Image.h"
#include "foundation/Math.h"
#include "shading/SphericalHarmonics.h"

#include <functional>
#include <vector>

namespace fp {

/// The most mips a cubemap has (a 2¹⁵-texel face).
constexpr int kMaxCubemapMips = 16;

/// Face and coordinates s, t ∈ [−1, 1] of a direction (OpenGL's cube lookup).
FP_HD inline void cubeFaceCoordinates(const Vec3f& d, int& face, float& s, float& t) {
    const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
    float ma, sc, tc;
    if (ax >= ay && ax >= az) {
        face = d.x >= 0 ? 0 : 1;
        ma = ax;
        sc = d.x >= 0 ? -d.z : d.z;
        tc = -d.y;
    } else if (ay >= az) {
        face = d.y >= 0 ? 2 : 3;
        ma = ay;
        sc = d.x;
        tc = d.y >= 0 ? d.z : -d.z;
    } else {
        face = d.z >= 0 ? 4 : 5;
        ma = az;
        sc = d.z >= 0 ? d.x : -d.x;
        tc = -d.y;
    }
    s = sc / ma;
    t = tc / ma;
}

/// Bilinear radiance in direction d from one mip's texels (face-major, then rows of `size`),
/// clamped at the face's edge texels: a seam of half a texel, finest at mip 0.
FP_HD inline Vec3f cubeBilinear(const Vec3f* texels, int size, const Vec3f& d) {
    int face;
    float s, t;
    cubeFaceCoordinates(d, face, s, t);
    const float hi = float(size - 1);
    float x = (s + 1.0f) * 0.5f * float(size) - 0.5f, y = (t + 1.0f) * 0.5f * float(size) - 0.5f;
    x = x < 0.0f ? 0.0f : (x > hi ? hi : x);
    y = y < 0.0f ? 0.0f : (y > hi ? hi : y);
    const int x0 = int(x) < size - 1 ? int(x) : size - 1, y0 = int(y) < size - 1 ? int(y) : size - 1;
    const int x1 = x0 + 1 < size - 1 ? x0 + 1 : size - 1, y1 = y0 + 1 < size - 1 ? y0 + 1 : size - 1;
    const float fx = x - float(x0), fy = y - float(y0);
    const Vec3f* f = texels + std::ptrdiff_t(face) * size * size;
    auto at = [&](int i, int j) { return f[std::ptrdiff_t(j) * size + i]; };
    return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) +
           (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
}

/// A cubemap as per-pixel code reads it, on the host or (its texels copied) on the GPU.
struct CubemapView {
    const Vec3f* mips[kMaxCubemapMips] = {};  //!< each mip's texels, face-major
    int mipSize[kMaxCubemapMips] = {};
    int mipCount = 0;

    /// Unreal's ComputeReflectionCaptureMipFromRoughness: (log2(size) − 1) − (1 − 1.2·log2 r),
    /// with r floored at 0.001. Not clamped; sample() clamps.
    FP_HD float mipForRoughness(float roughness) const {
        const float maxMip = log2Float(float(mipSize[0]));
        return (maxMip - 1.0f) - (1.0f - 1.2f * log2Float(roughness > 0.001f ? roughness : 0.001f));
    }
    /// Trilinear radiance in direction d (any length > 0) at fractional mip `mip` (clamped).
    FP_HD Vec3f sample(const Vec3f& d, float mip) const {
        const float top = float(mipCount - 1);
        const float m = std::isnan(mip) ? 0.0f : (mip < 0.0f ? 0.0f : (mip > top ? top : mip));
        const int m0 = int(m), m1 = m0 + 1 < mipCount - 1 ? m0 + 1 : mipCount - 1;
        const float f = m - float(m0);
        const Vec3f a = cubeBilinear(mips[m0], mipSize[m0], d);
        return f > 0.0f ? a * (1 - f) + cubeBilinear(mips[m1], mipSize[m1], d) * f : a;
    }
    /// The same view over a copy of the texels starting at `base` (laid out as the cubemap's).
    CubemapView rebased(const Vec3f* from, const Vec3f* base) const {
        CubemapView v = *this;
        for (int m = 0; m < mipCount; ++m) v.mips[m] = base + (mips[m] - from);
        return v;
    }
};

class Cubemap {
public:
    /// Renders `size`² texels a face from `radiance(direction)`, 2×2 samples a texel (so a finer
    /// source, a lat-long map, is averaged rather than point-sampled), then prefilters the mips.
    static Cubemap render(int size, const std::function<Vec3f(const Vec3f&)>& radiance);
    /// Unreal's sky light cubemap size (r.SkyLight… default 128): a sky light's radiance is
    /// resampled to it for the reflections and its SH.
    static constexpr int kSkyLightSize = 128;
    /// The same from faces already made: a strip of six `size`² faces stacked top to bottom
    /// (+X, −X, +Y, −Y, +Z, −Z), RGB, size a power of two.
    static Cubemap fromFaces(const Image& strip);
    /// The faces render() starts from, as such a strip.
    static Image renderFaces(int size, const std::function<Vec3f(const Vec3f&)>& radiance);

    int size() const { return mMipSizes.empty() ? 0 : mMipSizes.front(); }
    int mipCount() const { return int(mMipSizes.size()); }
    /// The view per-pixel code reads, into `texels()`: every mip's texels in one block (what a
    /// copy to the GPU takes; CubemapView::rebased points the view at the copy).
    CubemapView view() const;
    const std::vector<Vec3f>& texels() const { return mTexels; }

    Vec3f sample(const Vec3f& d, float mip) const { return view().sample(d, mip); }
    float mipForRoughness(float roughness) const { return view().mipForRoughness(roughness); }
    /// Its inverse: the GGX roughness a mip is prefiltered with (clamped to 1; mip 0 is mirror).
    float roughnessForMip(int mip) const;
    static float roughnessForMip(int mip, int size);

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
    static std::vector<Mip> boxChain(Mip base);
    /// The mips packed into one block.
    void pack(const std::vector<Mip>& mips);
    std::vector<Vec3f> mTexels;
    std::vector<int> mMipSizes;
};

}  // namespace fp
