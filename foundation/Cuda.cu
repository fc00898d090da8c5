// The CUDA runtime behind Cuda.h (built where CMake found nvcc).
#include "foundation/Cuda.h"
#include "foundation/Error.h"

#include <cuda_runtime.h>

#include <algorithm>
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

// Freed memory goes back to a pool by size instead of to the driver: cudaMalloc, cudaFree and
// their page-locked host twins synchronise the GPU and cost tens of microseconds (the host ones
// milliseconds for a frame's plane), and a sequence allocates the same sizes every frame. A pool
// keeps the blocks freed while they come to at most kMaxFreeBytes, and gives back to the driver
// what would take it over.
class MemoryPool {
public:
    using Allocate = cudaError_t (*)(void**, std::size_t);
    using Free = cudaError_t (*)(void*);
    MemoryPool(Allocate allocate, Free free, const char* what)
        : mAllocate(allocate), mFree(free), mWhat(what) {}

    float* take(std::size_t bytes) {
        {
            std::lock_guard<std::mutex> lock(mMutex);
            auto it = mBlocks.find(bytes);
            if (it != mBlocks.end()) {
                float* p = it->second;
                mBlocks.erase(it);
                mFreeBytes -= bytes;
                return p;
            }
        }
        void* p = nullptr;
        check(mAllocate(&p, bytes), mWhat);
        return static_cast<float*>(p);
    }
    void give(std::size_t bytes, float* p) {
        std::lock_guard<std::mutex> lock(mMutex);
        if (mFreeBytes + bytes > kMaxFreeBytes) {
            mFree(p);
            return;
        }
        mBlocks.emplace(bytes, p);
        mFreeBytes += bytes;
    }

private:
    static constexpr std::size_t kMaxFreeBytes = std::size_t(8) << 30;
    Allocate mAllocate;
    Free mFree;
    const char* mWhat;
    std::mutex mMutex;
    std::multimap<std::size_t, float*> mBlocks;
    std::size_t mFreeBytes = 0;
};

MemoryPool& pool() {  // never destroyed: images may outlive static teardown
    static MemoryPool* p = new MemoryPool([](void** q, std::size_t n) { return cudaMalloc(q, n); },
                                          [](void* q) { return cudaFree(q); }, "allocating an image");
    return *p;
}

// Page-locked host memory for the images of a process that runs passes on the GPU.
MemoryPool& hostPool() {
    static MemoryPool* p = new MemoryPool([](void** q, std::size_t n) { return cudaMallocHost(q, n); },
                                          [](void* q) { return cudaFreeHost(q); },
                                          "allocating page-locked host memory");
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

DeviceTexture allocate(const std::vector<Extent>& mips, const std::vector<std::string>& channels,
                       bool zeroed) {
    std::vector<DeviceImage> levels;
    for (const Extent& e : mips)
        levels.push_back(allocateImage(e.width, e.height, channels, zeroed));
    return DeviceTexture(std::move(levels));
}

void usePinnedHostMemory() {
    static std::once_flag once;
    std::call_once(once, [] {
        HostMemory memory;
        memory.allocate = [](std::size_t bytes) -> void* { return hostPool().take(bytes); };
        memory.release = [](void* p, std::size_t bytes) { hostPool().give(bytes, static_cast<float*>(p)); };
        setHostMemory(memory);
    });
}

std::shared_ptr<void> allocateBytes(std::size_t bytes) {
    // Rounded up to a float so the memory shares the image pool.
    return pooledMemory(std::max<std::size_t>((bytes + 3) / 4 * 4, 4));
}

std::shared_ptr<void> uploadBytes(const void* data, std::size_t bytes) {
    const auto t0 = std::chrono::steady_clock::now();
    std::shared_ptr<void> memory = allocateBytes(bytes);
    if (bytes > 0)
        check(cudaMemcpy(memory.get(), data, bytes, cudaMemcpyHostToDevice), "uploading a table");
    gTotals.uploadBytes += bytes;
    gTotals.uploadSeconds += secondsSince(t0);
    return memory;
}

namespace {
// The texture's planes queued for copying to new device images on `stream`.
DeviceTexture copyToDevice(const Texture& texture, cudaStream_t stream) {
    std::vector<DeviceImage> levels;
    for (int m = 0; m < texture.mipCount(); ++m) {
        const Image& host = texture.mip(m);
        DeviceImage dev = allocateImage(host.width(), host.height(), host.channels(), false);
        for (int c = 0; c < host.channelCount(); ++c) {
            const Plane& src = host.plane(c);
            check(cudaMemcpy2DAsync(dev.plane(c).data, dev.stride() * sizeof(float), src.row(0),
                                    src.stride() * sizeof(float), src.width() * sizeof(float),
                                    src.height(), cudaMemcpyHostToDevice, stream),
                  "uploading an image");
            gTotals.uploadBytes += std::size_t(src.width()) * src.height() * sizeof(float);
        }
        levels.push_back(std::move(dev));
    }
    return DeviceTexture(std::move(levels));
}
}  // namespace

DeviceTexture upload(const Texture& texture) {
    const auto t0 = std::chrono::steady_clock::now();
    DeviceTexture result = copyToDevice(texture, cudaStreamLegacy);
    check(cudaStreamSynchronize(cudaStreamLegacy), "uploading an image");
    gTotals.uploadSeconds += secondsSince(t0);
    return result;
}

namespace {
// The upload stream: non-blocking, so its copies do not wait for the default stream's kernels
// (nor they for it, but where awaitUpload says). One batch of copies is timed by two events.
struct Uploads {
    std::mutex mutex;
    cudaStream_t stream = nullptr;
    cudaEvent_t first = nullptr, last = nullptr;
    bool pending = false;
};
Uploads& uploads() {
    static Uploads& u = *[] {
        auto* made = new Uploads;  // kept for the process, as the CUDA context is
        check(cudaStreamCreateWithFlags(&made->stream, cudaStreamNonBlocking), "creating a stream");
        check(cudaEventCreate(&made->first), "creating an event");
        check(cudaEventCreate(&made->last), "creating an event");
        return made;
    }();
    return u;
}
}  // namespace

DeviceTexture uploadAsync(const Texture& texture) {
    Uploads& u = uploads();
    std::lock_guard<std::mutex> lock(u.mutex);
    if (!u.pending) {
        check(cudaEventRecord(u.first, u.stream), "recording an event");
        u.pending = true;
    }
    DeviceTexture result = copyToDevice(texture, u.stream);
    cudaEvent_t arrived = nullptr;
    check(cudaEventCreateWithFlags(&arrived, cudaEventDisableTiming), "creating an event");
    check(cudaEventRecord(arrived, u.stream), "recording an event");
    check(cudaEventRecord(u.last, u.stream), "recording an event");
    result.setArrival(std::shared_ptr<void>(static_cast<void*>(arrived), [](void* e) {
        cudaEventDestroy(static_cast<cudaEvent_t>(e));
    }));
    return result;
}

void awaitUpload(const DeviceTexture& texture) {
    if (texture.arrival())
        check(cudaStreamWaitEvent(cudaStreamLegacy, static_cast<cudaEvent_t>(texture.arrival().get()), 0),
              "waiting for an upload");
}

void finishUploads() {
    Uploads& u = uploads();
    std::lock_guard<std::mutex> lock(u.mutex);
    if (!u.pending) return;
    check(cudaEventSynchronize(u.last), "uploading an image");
    float ms = 0.0f;
    check(cudaEventElapsedTime(&ms, u.first, u.last), "timing the uploads");
    gTotals.uploadSeconds += double(ms) * 1e-3;
    u.pending = false;
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

DeviceImage copyOnDevice(const DeviceImage& image) {
    DeviceImage copy = allocateImage(image.width(), image.height(), image.channels(), false);
    for (int c = 0; c < image.channelCount(); ++c)
        check(cudaMemcpy2D(copy.plane(c).data, copy.stride() * sizeof(float), image.plane(c).data,
                           image.stride() * sizeof(float), image.width() * sizeof(float),
                           image.height(), cudaMemcpyDeviceToDevice),
              "copying an image on the GPU");
    // A device-to-device copy does not wait for itself on the host: the caller's next stream may
    // be any.
    check(cudaDeviceSynchronize(), "copying an image on the GPU");
    return copy;
}

namespace detail {
int residentBlocks(const void* kernel, int threadsPerBlock) {
    // Read once, however many sessions (threads) launch first: C++ initialises a function's
    // static exactly once.
    static const int multiprocessors = [] {
        int device = 0, count = 0;
        check(cudaGetDevice(&device), "reading the GPU's multiprocessor count");
        check(cudaDeviceGetAttribute(&count, cudaDevAttrMultiProcessorCount, device),
              "reading the GPU's multiprocessor count");
        return count;
    }();
    int perMultiprocessor = 0;
    check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&perMultiprocessor, kernel,
                                                        threadsPerBlock, 0),
          "reading a kernel's occupancy");
    return std::max(1, multiprocessors * perMultiprocessor);
}
}  // namespace detail

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

unsigned long long* hostCounterBuffer(int count) {
    static unsigned long long* buffer = nullptr;
    static int capacity = 0;
    if (count > capacity) {
        cudaFreeHost(buffer);
        buffer = nullptr;
        check(cudaMallocHost(&buffer, sizeof(unsigned long long) * count), "allocating counters");
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
