#pragma once
// The CUDA backend's runtime, as the executor and the CLI see it: whether the backend exists and
// can run here, device memory, transfers and event timing. Cuda.cu implements it where CMake found
// nvcc; CudaUnavailable.cpp elsewhere, saying so. Kernels themselves live beside their passes
// (passes/<id>/<Pass>.cu) and launch through CudaLaunch.cuh.
#include "foundation/DeviceImage.h"
#include "foundation/Image.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace fp {
struct BvhView;
struct Ray;
}  // namespace fp

namespace fp::cuda {

/// True when this build compiled the CUDA kernels (nvcc was found at configure time).
bool built();
/// Empty when a CUDA device can run the kernels; otherwise why not, in words for the user.
std::string unavailableReason();
/// The GPU's name, e.g. "NVIDIA H100 80GB HBM3" (empty without one).
std::string deviceName();

/// Device images, one per extent, with the given channels: zero-filled, or as the memory pool
/// hands them out where the caller writes every pixel (`zeroed` false).
DeviceTexture allocate(const std::vector<Extent>& mips, const std::vector<std::string>& channels,
                       bool zeroed = true);
/// Uninitialised device memory of `bytes` bytes (scratch arrays of a pass).
std::shared_ptr<void> allocateBytes(std::size_t bytes);
/// From now on images are made in page-locked host memory (a pool; Image.h's setHostMemory), so
/// a capture read for the GPU and an output read back from it cross the bus without a staging
/// copy: about 8× the bandwidth of pageable memory on an H100 machine. Called by the executor
/// before it runs a plan on the GPU; idempotent.
void usePinnedHostMemory();
/// A copy on the device of `bytes` bytes of host memory (a pass's tables: a cubemap, a LUT).
std::shared_ptr<void> uploadBytes(const void* data, std::size_t bytes);
DeviceTexture upload(const Texture& texture);
/// Starts copying `texture` to the GPU on the upload stream, a stream of its own that runs beside
/// the kernels, and returns the device copy at once: a frame's capture crosses while its first
/// passes run. The host images must stay as they are until finishUploads().
DeviceTexture uploadAsync(const Texture& texture);
/// Makes the kernels launched after this wait (on the GPU, not the host) until `texture` has
/// arrived; nothing for a texture not uploaded by uploadAsync.
void awaitUpload(const DeviceTexture& texture);
/// Waits for every uploadAsync so far and books their time, from the first copy's start to the
/// last one's end on the upload stream, in the transfer totals.
void finishUploads();
Texture download(const DeviceTexture& texture);
/// A copy of `image` in new device memory, finished when this returns (a door hands it to a
/// caller that may write into it, where the original is the library's own).
DeviceImage copyOnDevice(const DeviceImage& image);
/// Waits for the GPU; a failed kernel becomes an fp::Error naming `what`.
void synchronize(const char* what);
/// Device memory for `count` work counters, kept for the process (one launch uses it at a time:
/// kernels run in order on the default stream).
unsigned long long* counterBuffer(int count);
/// Page-locked host memory the counters are read back into (a copy to pageable memory is staged
/// through a driver buffer: a few microseconds more on every counting launch).
unsigned long long* hostCounterBuffer(int count);
/// Throws an fp::Error naming `what` unless `cudaStatus` (a cudaError_t) is cudaSuccess.
void checkStatus(int cudaStatus, const char* what);

/// Bytes moved between host and device since the process started (for the run report).
struct TransferTotals {
    std::size_t uploadBytes = 0, downloadBytes = 0;
    double uploadSeconds = 0, downloadSeconds = 0;
};
TransferTotals transferTotals();

/// Elapsed GPU time between two CUDA events on the default stream.
class EventTimer {
public:
    EventTimer();
    ~EventTimer();
    EventTimer(const EventTimer&) = delete;
    EventTimer& operator=(const EventTimer&) = delete;
    void start();
    void stop();
    /// Seconds between start() and stop(); waits for the stop event.
    double seconds();

private:
    struct Events;
    std::unique_ptr<Events> mEvents;
};

/// The yardstick for rt_shadows' GPU speed, as app::timeBareOcclusion is on the CPU: the same
/// rays (RayScene.h's, from host memory, copied to the GPU first) traced by a bare kernel, one
/// thread a ray, through `bvh` (a RayScene::deviceBvh()): occlusion, and with `closestHits` the
/// closest blocker (Bvh.h's traceBlocker), as the pass asks. Returns the median GPU seconds of
/// `runs` launches (CUDA events); `blocked` receives the occluded rays, so the work is checked and
/// kept.
double timeBareTraversal(const BvhView& bvh, const std::vector<Ray>& rays, bool closestHits,
                         int runs, uint64_t& blocked);

}  // namespace fp::cuda
