#pragma once
// Planar float32 images (architecture anchors B6): one 64-byte-aligned plane per channel, rows
// padded to 16 floats so every row starts on a cache line and inner loops vectorize. An image's
// planes are allocated as one block, one after the other, so its pixels can be handed out as a
// single (channel, row, column) array without a copy (the Python module's planar view).
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace fp {

/// Where the pixels of images made from now on come from. By default the C++ heap; the GPU
/// backend installs page-locked memory (cuda::usePinnedHostMemory), which the GPU copies to and
/// from at the bus's speed rather than through a staging copy. `allocate` returns at least
/// `bytes` bytes aligned to 64; `release` takes them back with the same size.
struct HostMemory {
    void* (*allocate)(std::size_t bytes) = nullptr;
    void (*release)(void* memory, std::size_t bytes) = nullptr;
};
/// `bytes` of uninitialised host memory, 64-byte aligned: what images, a pass's scratch arrays and
/// the EXR writer's half copies are made in. Large blocks come from a pool that recycles them
/// (Image.cpp), so a frame's memory does not fault its pages in afresh.
std::shared_ptr<void> hostScratch(std::size_t bytes);
/// Installs `memory` for the images made after it (a default HostMemory: the heap again). Images
/// made before keep the memory they have and give it back where it came from.
void setHostMemory(HostMemory memory);

/// One channel of floats, `width × height`, rows `stride` floats apart.
class Plane {
public:
    Plane() = default;
    Plane(int width, int height, float fill = 0.0f);

    int width() const { return mWidth; }
    int height() const { return mHeight; }
    std::ptrdiff_t stride() const { return mStride; }
    bool empty() const { return !mData; }
    float* row(int y) { return mData.get() + y * mStride; }
    const float* row(int y) const { return mData.get() + y * mStride; }
    float& at(int x, int y) { return row(y)[x]; }
    float at(int x, int y) const { return row(y)[x]; }
    /// Reads with coordinates clamped to the plane (the GPU's clamp addressing).
    float clampedAt(int x, int y) const;
    std::size_t bytes() const { return std::size_t(mStride) * mHeight * sizeof(float); }

private:
    friend class Image;
    /// A plane inside `block` (shared with the image's other planes), starting at `data`.
    Plane(const std::shared_ptr<float>& block, float* data, int width, int height,
          std::ptrdiff_t stride)
        : mData(block, data), mWidth(width), mHeight(height), mStride(stride) {}
    std::shared_ptr<float> mData;
    int mWidth = 0, mHeight = 0;
    std::ptrdiff_t mStride = 0;
};

/// A set of equally sized planes with channel names (e.g. R G B, or X Y Z).
class Image {
public:
    Image() = default;
    Image(int width, int height, std::vector<std::string> channels, float fill = 0.0f);
    /// The pixels left as the memory held them (whatever a recycled block last held): for an
    /// image its maker writes in full before anyone reads it.
    struct Uncleared {};
    Image(int width, int height, std::vector<std::string> channels, Uncleared);

    int width() const { return mWidth; }
    int height() const { return mHeight; }
    int channelCount() const { return int(mPlanes.size()); }
    const std::vector<std::string>& channels() const { return mChannels; }
    Plane& plane(int c) { return mPlanes[c]; }
    const Plane& plane(int c) const { return mPlanes[c]; }
    std::size_t bytes() const;
    /// The first plane's pixels when every plane follows the one before it in memory (plane c
    /// starts c × height × stride floats after plane 0, as the constructor lays them out), else
    /// nullptr (planes put together from other images).
    const float* planarData() const;

private:
    std::size_t planeFloats() const;   // one plane's floats, rows padded
    std::size_t planesFloats() const;  // every plane's
    void layPlanes(const std::shared_ptr<float>& block);  // the planes, one after another
    int mWidth = 0, mHeight = 0;
    std::vector<std::string> mChannels;
    std::vector<Plane> mPlanes;
};

/// Copies the pixels of `from` into `to`, which has its size and at least its channels. (Copying
/// an Image itself shares its planes; this is the copy with pixels of its own.)
void copyPixels(const Image& from, Image& to);

/// What flows along a graph edge: one image, or a mip chain (HZB, reduced colour) whose level 0
/// may be smaller than the frame.
class Texture {
public:
    Texture() = default;
    explicit Texture(Image level0) { mMips.push_back(std::move(level0)); }
    explicit Texture(std::vector<Image> mips) : mMips(std::move(mips)) {}

    int mipCount() const { return int(mMips.size()); }
    Image& mip(int level) { return mMips[level]; }
    const Image& mip(int level) const { return mMips[level]; }
    const Image& image() const { return mMips.front(); }
    Image& image() { return mMips.front(); }
    bool empty() const { return mMips.empty(); }
    std::size_t bytes() const;

private:
    std::vector<Image> mMips;
};

/// Width × height of an image; used to declare output sizes before pixels exist.
struct Extent {
    int width = 0, height = 0;
    bool operator==(const Extent&) const = default;
};

/// The bytes an Image of `channels` planes of extent `e` holds: each row padded to 64 bytes, as
/// the constructor lays planes out.
inline std::size_t imageBytes(Extent e, int channels) {
    const std::size_t rowFloats = (std::size_t(e.width) + 15) / 16 * 16;
    return rowFloats * std::size_t(e.height) * sizeof(float) * std::size_t(channels);
}
/// The same for a mip chain.
inline std::size_t imageBytes(const std::vector<Extent>& mips, int channels) {
    std::size_t sum = 0;
    for (const Extent& e : mips) sum += imageBytes(e, channels);
    return sum;
}

/// `levels` extents starting at `level0`, each half the previous (rounded down, at least 1), as
/// GPU mip chains are sized.
std::vector<Extent> mipChain(Extent level0, int levels);

}  // namespace fp
