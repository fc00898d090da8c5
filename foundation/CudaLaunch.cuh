#pragma once
// CudaPixels, the GPU's side of PerPixel.h. forEach: one thread per pixel in 16×8 blocks calling
// the same FP_HD function the CPU tile loop calls. forEachInSteps: as many threads as the GPU
// holds at once, each taking the next pixel when its own is done. Either sums the work counters
// per block in shared memory (a warp's first reduced by shuffles) and adds them once per block to
// the totals. The function objects are __grid_constant__ kernel parameters, so a pass's frame
// description is read from constant memory, not copied per thread.
#include "foundation/Cuda.h"
#include "foundation/PerPixel.h"

#include <cuda_runtime.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace fp::cuda {

namespace detail {
// Each counter summed across the warp by shuffles, then one shared atomic a warp, then one global
// atomic a block: 128 threads adding to one 64-bit counter each would wait on each other in turn.
// Every thread of the block calls it; blockSums was zeroed before a __syncthreads.
template <int N>
__device__ void addBlockCounts(const WorkCounts<N>& local, unsigned long long* blockSums,
                               unsigned long long* totals) {
    const int lane = threadIdx.y * blockDim.x + threadIdx.x;
    for (int i = 0; i < N; ++i) {
        unsigned long long v = local.value[i];
        for (int offset = 16; offset > 0; offset /= 2)
            v += __shfl_down_sync(0xffffffffu, v, offset);
        if ((lane & 31) == 0 && v)
            atomicAdd(&blockSums[i], v);
    }
    __syncthreads();
    if (lane < N && blockSums[lane])
        atomicAdd(&totals[lane], blockSums[lane]);
}

// 128 threads per block and at least 8 blocks per SM: registers are capped at 64 per thread,
// which doubled SSGI's occupancy (92 registers before) and cut its time by a fifth on the H100.
template <int N, class F>
__global__ void __launch_bounds__(128, 8)
    perPixel(int width, int height, const __grid_constant__ F f, unsigned long long* totals) {
    __shared__ unsigned long long blockSums[N > 0 ? N : 1];
    const int lane = threadIdx.y * blockDim.x + threadIdx.x;
    if (lane < N)
        blockSums[lane] = 0;
    if (N > 0)
        __syncthreads();
    const int x = blockIdx.x * blockDim.x + threadIdx.x;
    const int y = blockIdx.y * blockDim.y + threadIdx.y;
    WorkCounts<N> local{};
    if (x < width && y < height)
        f(x, y, local);
    if constexpr (N > 0)
        addBlockCounts<N>(local, blockSums, totals);
}

// forEachInSteps' kernel: as many threads as the GPU holds at once, each looping until no pixel
// is left. At the top of each round the warp's idle threads (pixel done, or none yet) take the
// next pixels, one atomic on the queue head `next` a warp; then every thread with a pixel takes
// one step. Pixels are handed out in 8×4 squares (`count` places: 32 a square, the squares
// covering the grid), 32 at a time to a full warp at the start, so a warp's first rays start close
// together, as PixelBlock::Squares's do. (One thread a pixel left a warp waiting for its longest
// pixel: on a terrain, whose paths run one to three rays, 5 of a warp's 32 threads were busy.)
template <int N, class State, class Begin, class Step>
__global__ void __launch_bounds__(128, 8)
    inSteps(int width, int height, unsigned long long count, const __grid_constant__ Begin begin,
            const __grid_constant__ Step step, unsigned long long* next,
            unsigned long long* totals) {
    __shared__ unsigned long long blockSums[N > 0 ? N : 1];
    if (threadIdx.x < N)
        blockSums[threadIdx.x] = 0;
    if (N > 0)
        __syncthreads();
    constexpr unsigned kWarp = 0xffffffffu;
    const unsigned lane = threadIdx.x & 31u;
    const unsigned squaresX = unsigned(width + 7) / 8;
    WorkCounts<N> local{};
    State state{};
    bool busy = false;
    bool more = true;  // the same in every thread of the warp: pixels may be left to hand out
    for (;;) {
        if (more) {
            const unsigned idle = __ballot_sync(kWarp, !busy);
            if (idle) {
                const int leader = __ffs(int(idle)) - 1;
                unsigned long long first = 0;
                if (int(lane) == leader)
                    first = atomicAdd(next, (unsigned long long)__popc(int(idle)));
                first = __shfl_sync(kWarp, first, leader);
                more = first + unsigned(__popc(int(idle))) < count;
                if (!busy) {
                    const unsigned long long i =
                        first + unsigned(__popc(int(idle & ((1u << lane) - 1u))));
                    const unsigned square = unsigned(i / 32), in = unsigned(i % 32);
                    const int x = int((square % squaresX) * 8 + (in & 7u));
                    const int y = int((square / squaresX) * 4 + (in >> 3));
                    if (i < count && x < width && y < height) {
                        state = State{};  // each pixel begins in a default-made State (PerPixel.h)
                        busy = begin(x, y, state, local);
                    }
                }
            }
        }
        if (!__any_sync(kWarp, busy)) {
            if (!more)
                break;
            continue;
        }
        if (busy)
            busy = step(state, local);
    }
    if constexpr (N > 0)
        addBlockCounts<N>(local, blockSums, totals);
}

/// How many blocks of `kernel` (threadsPerBlock threads each) the GPU holds at once.
int residentBlocks(const void* kernel, int threadsPerBlock);
}  // namespace detail

/// The N counters at `device` once the kernels before have finished (the copy waits for them, so
/// a failure inside one surfaces here, named by `what`).
template <int N>
std::array<uint64_t, N> readCounters(const unsigned long long* device, const char* what) {
    std::array<uint64_t, N> result{};
    if constexpr (N == 0) {
        synchronize(what);  // nothing to copy, but the caller still waits for its kernel
    } else {
        unsigned long long* host = hostCounterBuffer(N);
        checkStatus(
            cudaMemcpy(host, device, sizeof(unsigned long long) * N, cudaMemcpyDeviceToHost), what);
        for (int i = 0; i < N; ++i)
            result[i] = host[i];
    }
    return result;
}

/// How a block's 128 threads lie on the pixels. Rows: 16×8 (a warp reads 16 neighbours of two
/// rows: the widest memory transactions, for passes that stream their images). Squares: 8×16 (a
/// warp covers 8×4 pixels, so a ray-tracing pass's rays start closer together and take more of
/// the same way through the BVH: rt_shadows on the terrain 0.84 → 0.82 ms on the H100, where
/// the streaming passes lost as much as that).
enum class PixelBlock { Rows, Squares };

/// Runs f(x, y, WorkCounts<N>&) for every pixel of a width × height grid and returns the summed
/// counters, waiting for the kernel. With N = 0 nothing is counted and nothing waits: launches
/// queue up behind each other (a failure inside surfaces at the pass's end, when the executor
/// reads its CUDA events). `what` names the pass in errors.
template <int N, class F>
std::array<uint64_t, N> forEachPixel(int width, int height, const F& f, const char* what,
                                     PixelBlock shape = PixelBlock::Rows) {
    if (width <= 0 || height <= 0)
        return {};
    unsigned long long* totals = N > 0 ? counterBuffer(N) : nullptr;
    if (N > 0)
        checkStatus(cudaMemsetAsync(totals, 0, sizeof(unsigned long long) * N), what);
    const dim3 block = shape == PixelBlock::Rows ? dim3(16, 8) : dim3(8, 16);
    const dim3 grid((width + block.x - 1) / block.x, (height + block.y - 1) / block.y);
    detail::perPixel<N><<<grid, block>>>(width, height, f, totals);
    checkStatus(cudaGetLastError(), what);
    if constexpr (N == 0)
        return {};
    else
        return readCounters<N>(totals, what);
}

/// forEachInSteps (PerPixel.h) on the GPU: one launch of as many threads as the GPU holds at once
/// (fewer for a small grid), each taking pixels until none is left (detail::inSteps); waits for
/// the kernel and returns the summed counters. `what` names the pass in errors.
template <int N, class State, class Begin, class Step>
std::array<uint64_t, N> forEachPixelInSteps(int width, int height, const Begin& begin,
                                            const Step& step, const char* what) {
    if (width <= 0 || height <= 0)
        return {};
    // The counters, then the queue's head.
    unsigned long long* counters = counterBuffer(N + 1);
    checkStatus(cudaMemsetAsync(counters, 0, sizeof(unsigned long long) * (N + 1)), what);
    constexpr int kThreads = 128;
    auto kernel = detail::inSteps<N, State, Begin, Step>;
    // Places in the queue: 32 an 8×4 square, the squares covering the grid.
    const unsigned long long pixels = 32ull * unsigned((width + 7) / 8) * unsigned((height + 3) / 4);
    const int blocks = int(std::min<unsigned long long>(
        unsigned(detail::residentBlocks(reinterpret_cast<const void*>(kernel), kThreads)),
        (pixels + kThreads - 1) / kThreads));
    kernel<<<blocks, kThreads>>>(width, height, pixels, begin, step, counters + N, counters);
    checkStatus(cudaGetLastError(), what);
    return readCounters<N>(counters, what);
}

/// Counters every pixel of a launch adds to (addSharedCount, PerPixel.h), in device memory of
/// their own and zeroed; totals() waits for the kernels before it and reads them.
class SharedCounters {
public:
    SharedCounters(int count, const char* what)
        : mCount(count), mWhat(what), mMemory(allocateBytes(sizeof(unsigned long long) * count)) {
        checkStatus(cudaMemsetAsync(data(), 0, sizeof(unsigned long long) * count), what);
    }
    unsigned long long* data() const { return static_cast<unsigned long long*>(mMemory.get()); }
    std::vector<unsigned long long> totals() const {
        std::vector<unsigned long long> host(mCount);
        // The copy waits for the kernel; a failure inside it surfaces here.
        checkStatus(cudaMemcpy(host.data(), data(), sizeof(unsigned long long) * mCount,
                               cudaMemcpyDeviceToHost),
                    mWhat);
        return host;
    }

private:
    int mCount;
    const char* mWhat;
    std::shared_ptr<void> mMemory;
};

}  // namespace fp::cuda

namespace fp {
/// The GPU backend for a pass's run template (PerPixel.h).
struct CudaPixels {
    /// How forEach's blocks lie on the pixels (forEachInSteps hands out 8×4 squares itself).
    cuda::PixelBlock shape = cuda::PixelBlock::Rows;
    template <int N, class F>
    std::array<uint64_t, N> forEach(int width, int height, const F& fn, const char* what) const {
        return cuda::forEachPixel<N>(width, height, fn, what, shape);
    }
    /// A thread takes the next pixel when its own is done (forEachPixelInSteps); each pixel's
    /// steps run in order, so its bits are the CPU's.
    template <int N, class State, class Begin, class Step>
    std::array<uint64_t, N> forEachInSteps(int width, int height, const Begin& begin,
                                           const Step& step, const char* what) const {
        return cuda::forEachPixelInSteps<N, State>(width, height, begin, step, what);
    }
};
}  // namespace fp
