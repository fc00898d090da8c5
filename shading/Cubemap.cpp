#include "shading/Cubemap.h"

#include "foundation/Error.h"
#include "foundation/Sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace fp {

namespace {

double areaElement(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0)); }


}  // namespace

Vec3f Cubemap::direction(int face, float s, float t) {
    switch (face) {
        case 0: return normalize(Vec3f{1, -t, -s});
        case 1: return normalize(Vec3f{-1, -t, s});
        case 2: return normalize(Vec3f{s, 1, t});
        case 3: return normalize(Vec3f{s, -1, -t});
        case 4: return normalize(Vec3f{s, -t, 1});
        default: return normalize(Vec3f{-s, -t, -1});
    }
}

double Cubemap::texelSolidAngle(int x, int y, int size) {
    const double inv = 1.0 / size;
    const double x0 = 2.0 * x * inv - 1.0, x1 = x0 + 2.0 * inv;
    const double y0 = 2.0 * y * inv - 1.0, y1 = y0 + 2.0 * inv;
    return areaElement(x0, y0) - areaElement(x0, y1) - areaElement(x1, y0) + areaElement(x1, y1);
}

void Cubemap::pack(const std::vector<Mip>& mips) {
    FP_CHECK(int(mips.size()) <= kMaxCubemapMips, "a cubemap of {} mips: at most {}", mips.size(),
             kMaxCubemapMips);
    mTexels.clear();
    mMipSizes.clear();
    for (const Mip& m : mips) {
        mMipSizes.push_back(m.size);
        mTexels.insert(mTexels.end(), m.texels.begin(), m.texels.end());
    }
}

CubemapView Cubemap::view() const {
    CubemapView v;
    v.mipCount = mipCount();
    const Vec3f* texels = mTexels.data();
    for (int m = 0; m < v.mipCount; ++m) {
        v.mipSize[m] = mMipSizes[size_t(m)];
        v.mips[m] = texels;
        texels += std::ptrdiff_t(6) * v.mipSize[m] * v.mipSize[m];
    }
    return v;
}

std::vector<Cubemap::Mip> Cubemap::boxChain(Mip base) {
    std::vector<Mip> chain{std::move(base)};
    while (chain.back().size > 1) {
        const Mip& up = chain.back();
        Mip m;
        m.size = up.size / 2;
        m.texels.resize(size_t(6) * m.size * m.size);
        for (int f = 0; f < 6; ++f)
            for (int y = 0; y < m.size; ++y)
                for (int x = 0; x < m.size; ++x)
                    m.texels[(size_t(f) * m.size + size_t(y)) * m.size + size_t(x)] =
                        (up.at(f, 2 * x, 2 * y) + up.at(f, 2 * x + 1, 2 * y) +
                         up.at(f, 2 * x, 2 * y + 1) + up.at(f, 2 * x + 1, 2 * y + 1)) * 0.25f;
        chain.push_back(std::move(m));
    }
    return chain;
}

Image Cubemap::renderFaces(int size, const std::function<Vec3f(const Vec3f&)>& radiance) {
    FP_CHECK(size >= 1 && (size & (size - 1)) == 0, "a cubemap face of {} texels: not a power of two", size);
    Image strip(size, 6 * size, {"R", "G", "B"});
    tbb::parallel_for(0, 6 * size, [&](int row) {
        const int f = row / size, y = row % size;
        for (int x = 0; x < size; ++x) {
            Vec3f sum;
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i)
                    sum += radiance(direction(f, (2.0f * (x + 0.25f + 0.5f * i)) / size - 1.0f,
                                              (2.0f * (y + 0.25f + 0.5f * j)) / size - 1.0f));
            for (int c = 0; c < 3; ++c) strip.plane(c).at(x, row) = sum[c] * 0.25f;
        }
    });
    return strip;
}

Cubemap Cubemap::render(int size, const std::function<Vec3f(const Vec3f&)>& radiance) {
    return fromFaces(renderFaces(size, radiance));
}

Cubemap Cubemap::fromFaces(const Image& strip) {
    const int size = strip.width();
    FP_CHECK(size >= 1 && (size & (size - 1)) == 0 && strip.height() == 6 * size && strip.channelCount() >= 3,
             "a cubemap strip of {}×{}: expected 6 square power-of-two faces stacked", strip.width(),
             strip.height());
    Cubemap cube;
    std::vector<Mip> mips;
    Mip base;
    base.size = size;
    base.texels.resize(size_t(6) * size * size);
    for (int row = 0; row < 6 * size; ++row)
        for (int x = 0; x < size; ++x)
            base.texels[size_t(row) * size + size_t(x)] = {strip.plane(0).at(x, row), strip.plane(1).at(x, row),
                                                           strip.plane(2).at(x, row)};
    // Each prefiltered mip integrates the GGX lobe over the box-filtered source chain, reading
    // each sample at the mip whose texel covers the sample's share of the lobe (filtered
    // importance sampling, Křivánek & Colbert 2008), so 64 samples leave no visible noise.
    const std::vector<Mip> source = boxChain(base);
    mips.push_back(std::move(base));
    const double texelAngle0 = 4.0 * kPi / (6.0 * double(size) * size);
    for (int m = 1; m < int(source.size()); ++m) {
        Mip out;
        out.size = source[size_t(m)].size;
        out.texels.resize(size_t(6) * out.size * out.size);
        // The lobe's samples in its tangent frame, with the source mip each is read at: the same
        // for every texel of this mip, so they are made once.
        struct LobeSample {
            float x, y, z;  // L in the frame (t, b, N)
            float NoL, lod;
        };
        std::vector<LobeSample> lobe;
        const float roughness = roughnessForMip(m, size);
        const float a2 = roughness * roughness * roughness * roughness;
        for (int i = 0; i < kPrefilterSamples; ++i) {
            const float e1 = float(i) / kPrefilterSamples, e2 = float(radicalInverse2(uint32_t(i)));
            const float cosT = std::sqrt((1.0f - e2) / (1.0f + (a2 - 1.0f) * e2));
            const float sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
            const float phi = 2.0f * kPiF * e1;
            const Vec3f H{sinT * std::cos(phi), sinT * std::sin(phi), cosT};
            const Vec3f L = reflect(Vec3f{0, 0, 1}, H);  // N = V = R (the split-sum assumption)
            if (L.z <= 0.0f) continue;
            // pdf over L with V = N: D·NoH/(4·VoH) = D/4.
            const float d = (cosT * a2 - cosT) * cosT + 1.0f;
            const double pdf = a2 / (kPi * d * d) / 4.0;
            const double sampleAngle = 1.0 / (kPrefilterSamples * pdf);
            const float lod = std::clamp(float(0.5 * std::log2(sampleAngle / texelAngle0)) + 1.0f, 0.0f,
                                         float(source.size() - 1));
            lobe.push_back({L.x, L.y, L.z, L.z, lod});
        }
        tbb::parallel_for(0, 6 * out.size, [&](int row) {
            const int f = row / out.size, y = row % out.size;
            for (int x = 0; x < out.size; ++x) {
                const Vec3f N = direction(f, (2.0f * x + 1.0f) / out.size - 1.0f,
                                          (2.0f * y + 1.0f) / out.size - 1.0f);
                Vec3f tb, bb;
                orthonormalBasis(N, tb, bb);
                Vec3f sum;
                float weight = 0.0f;
                for (const LobeSample& l : lobe) {
                    const Vec3f L = tb * l.x + bb * l.y + N * l.z;
                    const int l0 = int(l.lod), l1 = std::min(l0 + 1, int(source.size()) - 1);
                    const float fl = l.lod - float(l0);
                    const Mip &s0 = source[size_t(l0)], &s1 = source[size_t(l1)];
                    const Vec3f c = fl > 0.0f ? cubeBilinear(s0.texels.data(), s0.size, L) * (1 - fl) +
                                                    cubeBilinear(s1.texels.data(), s1.size, L) * fl
                                              : cubeBilinear(s0.texels.data(), s0.size, L);
                    sum += c * l.NoL;
                    weight += l.NoL;
                }
                out.texels[(size_t(f) * out.size + size_t(y)) * out.size + size_t(x)] =
                    weight > 0.0f ? sum / weight : Vec3f{};
            }
        });
        mips.push_back(std::move(out));
    }
    cube.pack(mips);
    return cube;
}

float Cubemap::roughnessForMip(int mip) const { return roughnessForMip(mip, size()); }

float Cubemap::roughnessForMip(int mip, int size) {
    const float maxMip = std::log2(float(size));
    return std::min(1.0f, std::exp2((float(mip) - maxMip + 2.0f) / 1.2f));
}

SH3 Cubemap::projectSH() const {
    SH3 sh;
    const int size = this->size();
    const Vec3f* texels = mTexels.data();
    for (int f = 0; f < 6; ++f)
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x)
                sh.add(direction(f, (2.0f * x + 1.0f) / size - 1.0f, (2.0f * y + 1.0f) / size - 1.0f),
                       texels[(size_t(f) * size + size_t(y)) * size + size_t(x)],
                       float(texelSolidAngle(x, y, size)));
    return sh;
}

}  // namespace fp
