#include "foundation/Image.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <map>
#include <mutex>
#include <new>
#include <vector>

#include <malloc.h>

namespace fp {

namespace {
constexpr std::ptrdiff_t kRowAlignFloats = 16;  // 64 bytes

// Images of 4 MiB and more are mapped from the system and given back when freed. glibc otherwise
// raises its mmap threshold to the largest block freed so far (up to 32 MiB), after which a
// frame's images come from the heaps of the worker threads' arenas, which keep what they free:
// a run's resident memory then grew by a third over three 1024² frames (the read-ahead's buffers
// freed in another thread's arena) and stopped matching the forecast --max-memory is checked
// against. A fixed threshold also turns the dynamic adjustment off.
[[maybe_unused]] const bool kLargeImagesMapped = [] {
#ifdef M_MMAP_THRESHOLD
    return mallopt(M_MMAP_THRESHOLD, 4 << 20) == 1;
#else
    return false;
#endif
}();

std::ptrdiff_t rowStride(int width) {
    return (std::ptrdiff_t(width) + kRowAlignFloats - 1) / kRowAlignFloats * kRowAlignFloats;
}

/// The floats of a plane of `height` rows of `width`, each row padded to rowStride(width).
std::size_t paddedPlaneFloats(int width, int height) {
    return std::size_t(rowStride(width)) * std::size_t(height);
}

std::mutex gHostMemoryMutex;
HostMemory gHostMemory;

HostMemory hostMemory() {
    std::lock_guard<std::mutex> lock(gHostMemoryMutex);
    return gHostMemory;
}

// The mapped blocks of images recycled: a block freed is kept for the next image of its size (a
// sequence's frames ask for the same sizes frame after frame), so a frame's images neither fault
// their pages in afresh (the kernel zeroing each page on first touch) nor unmap them again (each
// unmap interrupting every core the process runs on to flush its TLB). A block is kept only while
// the blocks kept and the images alive stay under the most image memory ever alive at once plus
// one block of the largest size made: the process holds at most that one block more than it would
// without recycling, and the memory forecast stands. (Without the one block, a chain of ray-traced
// passes faulted 40 MB in every frame: a frame's first images are made while the last frame's
// outputs are still held, until this frame's replace them, so a frame needs one more plane than
// its peak; to make it, the block kept for a later pass's 33 MB output was given back, and made
// again when that pass ran.)
class BlockPool {
public:
    static constexpr std::size_t kMinBytes = std::size_t(4) << 20;  // the mapped ones
    void* take(std::size_t bytes) {
        std::vector<std::pair<void*, std::size_t>> released;
        {
            std::lock_guard<std::mutex> lock(mMutex);
            mLive += bytes;
            mMostLive = std::max(mMostLive, mLive);
            mLargest = std::max(mLargest, bytes);
            if (auto it = mFree.find(bytes); it != mFree.end()) {
                void* p = it->second;
                mFree.erase(it);
                mKept -= bytes;
                return p;
            }
            // A new block: the kept ones of other sizes go back where they would lift the memory
            // held above the bound.
            while (mLive + mKept > bound() && !mFree.empty()) {
                auto largest = std::prev(mFree.end());
                released.emplace_back(largest->second, largest->first);
                mKept -= largest->first;
                mFree.erase(largest);
            }
        }
        for (const auto& block : released) ::operator delete[](block.first, std::align_val_t{64});
        return ::operator new[](bytes, std::align_val_t{64});
    }
    void give(void* p, std::size_t bytes) {
        {
            std::lock_guard<std::mutex> lock(mMutex);
            mLive -= bytes;
            if (mLive + mKept + bytes <= bound()) {
                mFree.emplace(bytes, p);
                mKept += bytes;
                return;
            }
        }
        ::operator delete[](p, std::align_val_t{64});
    }

private:
    std::size_t bound() const { return mMostLive + mLargest; }
    std::mutex mMutex;
    std::multimap<std::size_t, void*> mFree;
    std::size_t mLive = 0, mKept = 0, mMostLive = 0, mLargest = 0;
};

BlockPool& blockPool() {
    static BlockPool* pool = new BlockPool;  // never destroyed: images may outlive statics
    return *pool;
}

// `count` floats (one at least), 64-byte aligned, as the memory held them.
std::shared_ptr<float> allocateBlock(std::size_t count) {
    const std::size_t bytes = std::max<std::size_t>(1, count) * sizeof(float);
    const HostMemory memory = hostMemory();
    const std::shared_ptr<void> block =
        memory.allocate ? std::shared_ptr<void>(memory.allocate(bytes),
                                                [release = memory.release, bytes](void* q) {
                                                    release(q, bytes);
                                                })
                        : hostScratch(bytes);
    return std::shared_ptr<float>(block, static_cast<float*>(block.get()));
}

// `count` floats set to `fill`, by blocks on all threads: a frame's plane is megabytes, and the
// first write of each fresh page also faults it in, which one thread would do serially.
std::shared_ptr<float> allocateFilled(std::size_t count, float fill) {
    std::shared_ptr<float> block = allocateBlock(count);
    float* p = block.get();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, std::max<std::size_t>(1, count),
                                                      std::size_t(1) << 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          std::fill(p + r.begin(), p + r.end(), fill);
                      });
    return block;
}

// With FRAMEPASS_POISON_UNCLEARED set (the test suite sets it for every test), an uncleared image
// starts as NaN instead: a pass that leaves a pixel of an output it promised to overwrite shows
// it in that output, which the tests compare.
const bool kPoisonUncleared = std::getenv("FRAMEPASS_POISON_UNCLEARED") != nullptr;

std::shared_ptr<float> allocateUncleared(std::size_t count) {
    return kPoisonUncleared ? allocateFilled(count, std::numeric_limits<float>::quiet_NaN())
                            : allocateBlock(count);
}
}  // namespace

std::shared_ptr<void> hostScratch(std::size_t bytes) {
    bytes = std::max<std::size_t>(1, bytes);
    if (bytes >= BlockPool::kMinBytes)
        return std::shared_ptr<void>(blockPool().take(bytes),
                                     [bytes](void* q) { blockPool().give(q, bytes); });
    return std::shared_ptr<void>(::operator new[](bytes, std::align_val_t{64}),
                                 [](void* q) { ::operator delete[](q, std::align_val_t{64}); });
}

void setHostMemory(HostMemory memory) {
    std::lock_guard<std::mutex> lock(gHostMemoryMutex);
    gHostMemory = memory;
}

Plane::Plane(int width, int height, float fill)
    : mData(allocateFilled(paddedPlaneFloats(width, height), fill)),
      mWidth(width),
      mHeight(height),
      mStride(rowStride(width)) {}

float Plane::clampedAt(int x, int y) const {
    x = std::clamp(x, 0, mWidth - 1);
    y = std::clamp(y, 0, mHeight - 1);
    return row(y)[x];
}

Image::Image(int width, int height, std::vector<std::string> channels, float fill)
    : mWidth(width), mHeight(height), mChannels(std::move(channels)) {
    if (!mChannels.empty()) layPlanes(allocateFilled(planesFloats(), fill));
}

Image::Image(int width, int height, std::vector<std::string> channels, Uncleared)
    : mWidth(width), mHeight(height), mChannels(std::move(channels)) {
    if (!mChannels.empty()) layPlanes(allocateUncleared(planesFloats()));
}

std::size_t Image::planeFloats() const {
    return paddedPlaneFloats(mWidth, std::max(mHeight, 0));
}

std::size_t Image::planesFloats() const { return planeFloats() * mChannels.size(); }

void Image::layPlanes(const std::shared_ptr<float>& block) {
    for (std::size_t c = 0; c < mChannels.size(); ++c)
        mPlanes.push_back(
            Plane(block, block.get() + c * planeFloats(), mWidth, mHeight, rowStride(mWidth)));
}

const float* Image::planarData() const {
    if (mPlanes.empty() || mPlanes[0].empty()) return nullptr;
    const float* first = mPlanes[0].row(0);
    for (std::size_t c = 1; c < mPlanes.size(); ++c)
        if (mPlanes[c].row(0) != first + std::ptrdiff_t(c) * mPlanes[0].stride() * mHeight ||
            mPlanes[c].stride() != mPlanes[0].stride())
            return nullptr;
    return first;
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
