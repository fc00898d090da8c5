// The CUDA runtime behind Cuda.h (built where CMake found nvcc).
#include "foundation/Cuda.h"
#include "foundation/Error.h"

#include <cuda_runtime.h>

#include <chrono>
#include <map>
#include <mutex>

namespace fp::cuda {

namespace {

void check(cudaError_t status, const char* what) {
    if (status != cudaSuccess)
        throw Error(fmt::format("CUDA: {}: {}", what, cudaGetErrorString(status)));
}

// Rows padded to 32 floats (128 bytes), so every row starts on a memory transaction.
std::ptrdiff_t paddedStride(int width) {
    return (std::ptrdiff_t(width) + 31) / 32 * 32;
}

// Freed device images go back to a pool by size instead of to the driver: cudaMalloc and cudaFree
// synchronise the GPU and cost tens of microseconds, and a sequence allocates the same sizes every
// frame. The pool holds at most what one frame held at its peak.
class DevicePool {
public:
    float* take(std::size_t bytes) {
        {
            std::lock_guard<std::mutex> lock(mMutex);
            auto it = mFree.find(bytes);
            if (it != mFree.end()) {
                float* p = it->second;
                mFree.erase(it);
                return p;
            }
        }
        float* p = nullptr;
        check(cudaMalloc(&p, bytes), "allocating an image");
        return p;
    }
    void give(std::size_t bytes, float* p) {
        std::lock_guard<std::mutex> lock(mMutex);
        mFree.emplace(bytes, p);
    }

private:
    std::mutex mMutex;
    std::multimap<std::size_t, float*> mFree;
};

DevicePool& pool() {
    static DevicePool* p = new DevicePool;  // never destroyed: images may outlive static teardown
    return *p;
}

// `bytes` of device memory from the pool, given back to it when the last owner lets go.
std::shared_ptr<float> pooledMemory(std::size_t bytes) {
    return std::shared_ptr<float>(pool().take(bytes), [bytes](float* q) { pool().give(bytes, q); });
}

// `zeroed`: outputs start at zero (the pass contract); an upload overwrites every row anyway.
DeviceImage allocateImage(int width, int height, const std::vector<std::string>& channels,
                          bool zeroed) {
    const std::ptrdiff_t stride = paddedStride(std::max(width, 1));
    const std::size_t bytes =
        std::size_t(stride) * std::max(height, 1) * std::max<std::size_t>(channels.size(), 1) *
        sizeof(float);
    std::shared_ptr<float> memory = pooledMemory(bytes);
    if (zeroed)
        check(cudaMemsetAsync(memory.get(), 0, bytes), "clearing an image");
    return DeviceImage(width, height, channels, std::move(memory), stride);
}

TransferTotals gTotals;

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

bool built() {
    return true;
}

std::string unavailableReason() {
    int count = 0;
    const cudaError_t status = cudaGetDeviceCount(&count);
    if (status != cudaSuccess)
        return fmt::format("no usable CUDA device ({})", cudaGetErrorString(status));
    if (count == 0)
        return "no CUDA device on this machine";
    return "";
}

std::string deviceName() {
    cudaDeviceProp prop{};
    if (!unavailableReason().empty() || cudaGetDeviceProperties(&prop, 0) != cudaSuccess)
        return "";
    return prop.name;
}

DeviceTexture allocate(const std::vector<Extent>& mips, const std::vector<std::string>& channels) {
    std::vector<DeviceImage> levels;
    for (const Extent& e : mips)
        levels.push_back(allocateImage(e.width, e.height, channels, true));
    return DeviceTexture(std::move(levels));
}

std::shared_ptr<void> allocateBytes(std::size_t bytes) {
    // Rounded up to a float so the memory shares the image pool.
    return pooledMemory(std::max<std::size_t>((bytes + 3) / 4 * 4, 4));
}

DeviceTexture upload(const Texture& texture) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<DeviceImage> levels;
    for (int m = 0; m < texture.mipCount(); ++m) {
        const Image& host = texture.mip(m);
        DeviceImage dev = allocateImage(host.width(), host.height(), host.channels(), false);
        for (int c = 0; c < host.channelCount(); ++c) {
            const Plane& src = host.plane(c);
            check(cudaMemcpy2D(dev.plane(c).data, dev.stride() * sizeof(float), src.row(0),
                               src.stride() * sizeof(float), src.width() * sizeof(float),
                               src.height(), cudaMemcpyHostToDevice),
                  "uploading an image");
            gTotals.uploadBytes += std::size_t(src.width()) * src.height() * sizeof(float);
        }
        levels.push_back(std::move(dev));
    }
    gTotals.uploadSeconds += secondsSince(t0);
    return DeviceTexture(std::move(levels));
}

Texture download(const DeviceTexture& texture) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Image> levels;
    for (int m = 0; m < texture.mipCount(); ++m) {
        const DeviceImage& dev = texture.mip(m);
        Image host(dev.width(), dev.height(), dev.channels());
        for (int c = 0; c < dev.channelCount(); ++c) {
            Plane& dst = host.plane(c);
            check(cudaMemcpy2D(dst.row(0), dst.stride() * sizeof(float), dev.plane(c).data,
                               dev.stride() * sizeof(float), dst.width() * sizeof(float),
                               dst.height(), cudaMemcpyDeviceToHost),
                  "downloading an image");
            gTotals.downloadBytes += std::size_t(dst.width()) * dst.height() * sizeof(float);
        }
        levels.push_back(std::move(host));
    }
    gTotals.downloadSeconds += secondsSince(t0);
    return Texture(std::move(levels));
}

unsigned long long* counterBuffer(int count) {
    static unsigned long long* buffer = nullptr;
    static int capacity = 0;
    if (count > capacity) {
        cudaFree(buffer);
        buffer = nullptr;
        check(cudaMalloc(&buffer, sizeof(unsigned long long) * count), "allocating counters");
        capacity = count;
    }
    return buffer;
}

void checkStatus(int cudaStatus, const char* what) {
    check(cudaError_t(cudaStatus), what);
}

void synchronize(const char* what) {
    check(cudaGetLastError(), what);
    check(cudaDeviceSynchronize(), what);
}

TransferTotals transferTotals() {
    return gTotals;
}

struct EventTimer::Events {
    cudaEvent_t start = nullptr, stop = nullptr;
};

EventTimer::EventTimer() : mEvents(std::make_unique<Events>()) {
    check(cudaEventCreate(&mEvents->start), "creating an event");
    check(cudaEventCreate(&mEvents->stop), "creating an event");
}

EventTimer::~EventTimer() {
    cudaEventDestroy(mEvents->start);
    cudaEventDestroy(mEvents->stop);
}

void EventTimer::start() {
    check(cudaEventRecord(mEvents->start), "recording an event");
}

void EventTimer::stop() {
    check(cudaEventRecord(mEvents->stop), "recording an event");
}

double EventTimer::seconds() {
    check(cudaEventSynchronize(mEvents->stop), "waiting for an event");
    float ms = 0.0f;
    check(cudaEventElapsedTime(&ms, mEvents->start, mEvents->stop), "reading an event");
    return double(ms) * 1e-3;
}

}  // namespace fp::cuda
