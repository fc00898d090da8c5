#pragma once
// Images resident on the GPU for the CUDA backend: the layout of Image (one plane per channel,
// rows padded to 32 floats) in one device allocation per image. Declared without CUDA headers so
// the executor and the passes can hold them in any build; only the runtime (Cuda.h) makes them.
#include "foundation/Image.h"
#include "foundation/PlaneView.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace fp {

class DeviceImage {
public:
    DeviceImage() = default;
    /// Wraps device memory of channels.size() planes, each `height` rows of `stride` floats.
    DeviceImage(int width, int height, std::vector<std::string> channels,
                std::shared_ptr<float> deviceMemory, std::ptrdiff_t stride)
        : mWidth(width),
          mHeight(height),
          mStride(stride),
          mChannels(std::move(channels)),
          mData(std::move(deviceMemory)) {}

    int width() const { return mWidth; }
    int height() const { return mHeight; }
    std::ptrdiff_t stride() const { return mStride; }
    int channelCount() const { return int(mChannels.size()); }
    const std::vector<std::string>& channels() const { return mChannels; }
    /// Device pointers: valid in kernels only.
    PlaneView plane(int c) const { return {planeData(c), mWidth, mHeight, mStride}; }
    PlaneSpan plane(int c) { return {planeData(c), mWidth, mHeight, mStride}; }
    std::size_t planeBytes() const { return std::size_t(mStride) * mHeight * sizeof(float); }
    std::size_t bytes() const { return planeBytes() * mChannels.size(); }

private:
    float* planeData(int c) const { return mData.get() + std::ptrdiff_t(c) * mStride * mHeight; }
    int mWidth = 0, mHeight = 0;
    std::ptrdiff_t mStride = 0;
    std::vector<std::string> mChannels;
    std::shared_ptr<float> mData;
};

/// A DeviceImage or a mip chain of them, as Texture is on the host.
class DeviceTexture {
public:
    DeviceTexture() = default;
    explicit DeviceTexture(std::vector<DeviceImage> mips) : mMips(std::move(mips)) {}

    int mipCount() const { return int(mMips.size()); }
    const DeviceImage& mip(int level) const { return mMips[level]; }
    DeviceImage& mip(int level) { return mMips[level]; }
    const DeviceImage& image() const { return mMips.front(); }
    DeviceImage& image() { return mMips.front(); }
    bool empty() const { return mMips.empty(); }
    std::size_t bytes() const {
        std::size_t b = 0;
        for (const auto& m : mMips)
            b += m.bytes();
        return b;
    }
    /// For a copy still crossing from the host (cuda::uploadAsync): the event that marks its
    /// arrival, which cuda::awaitUpload makes the kernels wait for; null once it is not pending.
    const std::shared_ptr<void>& arrival() const { return mArrival; }
    void setArrival(std::shared_ptr<void> event) { mArrival = std::move(event); }

private:
    std::vector<DeviceImage> mMips;
    std::shared_ptr<void> mArrival;
};

}  // namespace fp
