#include "foundation/Image.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <new>

namespace fp {

namespace {
constexpr std::ptrdiff_t kRowAlignFloats = 16;  // 64 bytes
}

void Plane::AlignedDelete::operator()(float* p) const {
    ::operator delete[](p, std::align_val_t{64});
}

Plane::Plane(int width, int height, float fill) : mWidth(width), mHeight(height) {
    mStride = (std::ptrdiff_t(width) + kRowAlignFloats - 1) / kRowAlignFloats * kRowAlignFloats;
    std::size_t count = std::max<std::size_t>(1, std::size_t(mStride) * std::size_t(height));
    float* p = static_cast<float*>(::operator new[](count * sizeof(float), std::align_val_t{64}));
    // Filled by row blocks on all threads: a frame's plane is megabytes, and the first write of
    // each fresh page also faults it in, which one thread would do serially.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, std::size_t(1) << 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          std::fill(p + r.begin(), p + r.end(), fill);
                      });
    mData = std::shared_ptr<float>(p, AlignedDelete{});
}

float Plane::clampedAt(int x, int y) const {
    x = std::clamp(x, 0, mWidth - 1);
    y = std::clamp(y, 0, mHeight - 1);
    return row(y)[x];
}

Image::Image(int width, int height, std::vector<std::string> channels, float fill)
    : mWidth(width), mHeight(height), mChannels(std::move(channels)) {
    for (std::size_t i = 0; i < mChannels.size(); ++i) mPlanes.emplace_back(width, height, fill);
}

void copyPixels(const Image& from, Image& to) {
    for (int c = 0; c < from.channelCount(); ++c)
        for (int y = 0; y < from.height(); ++y)
            std::copy_n(from.plane(c).row(y), from.width(), to.plane(c).row(y));
}

std::size_t Image::bytes() const {
    std::size_t b = 0;
    for (const auto& p : mPlanes) b += p.bytes();
    return b;
}

std::vector<Extent> mipChain(Extent level0, int levels) {
    std::vector<Extent> list;
    for (int m = 0; m < levels; ++m) {
        list.push_back(level0);
        level0 = {std::max(1, level0.width / 2), std::max(1, level0.height / 2)};
    }
    return list;
}

std::size_t Texture::bytes() const {
    std::size_t b = 0;
    for (const auto& m : mMips) b += m.bytes();
    return b;
}

}  // namespace fp
