#pragma once
// CudaPixels, the GPU's side of PerPixel.h: one thread per pixel in 16×8 blocks calling the same
// FP_HD function the CPU tile loop calls, with the work counters summed per block in shared
// memory and added once per block to the totals. The function object is a __grid_constant__
// kernel parameter, so a pass's frame description is read from constant memory, not copied
// per thread.
#include "passes/core/Cuda.h"
#include "passes/core/PerPixel.h"

#include <cuda_runtime.h>

#include <array>
#include <cstdint>

namespace fp::cuda {

namespace detail {
template <int N, class F>
__global__ void perPixel(int width, int height, const __grid_constant__ F f,
                         unsigned long long* totals) {
    __shared__ unsigned long long blockSums[N];
    const int lane = threadIdx.y * blockDim.x + threadIdx.x;
    if (lane < N)
        blockSums[lane] = 0;
    __syncthreads();
    const int x = blockIdx.x * blockDim.x + threadIdx.x;
    const int y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x < width && y < height) {
        WorkCounts<N> local{};
        f(x, y, local);
        for (int i = 0; i < N; ++i)
            if (local.value[i])
                atomicAdd(&blockSums[i], local.value[i]);
    }
    __syncthreads();
    if (lane < N && blockSums[lane])
        atomicAdd(&totals[lane], blockSums[lane]);
}
}  // namespace detail

/// Runs f(x, y, WorkCounts<N>&) for every pixel of a width × height grid and returns the summed
/// counters (waits for the kernel). `what` names the pass in errors.
template <int N, class F>
std::array<uint64_t, N> forEachPixel(int width, int height, const F& f, const char* what) {
    std::array<uint64_t, N> result{};
    if (width <= 0 || height <= 0)
        return result;
    struct DeviceTotals {
        unsigned long long* p = nullptr;
        ~DeviceTotals() { cudaFree(p); }
    } totals;
    checkStatus(cudaMalloc(&totals.p, sizeof(unsigned long long) * N), what);
    checkStatus(cudaMemset(totals.p, 0, sizeof(unsigned long long) * N), what);
    const dim3 block(16, 8);
    const dim3 grid((width + block.x - 1) / block.x, (height + block.y - 1) / block.y);
    detail::perPixel<N><<<grid, block>>>(width, height, f, totals.p);
    synchronize(what);
    unsigned long long host[N];
    checkStatus(cudaMemcpy(host, totals.p, sizeof host, cudaMemcpyDeviceToHost), what);
    for (int i = 0; i < N; ++i)
        result[i] = host[i];
    return result;
}

}  // namespace fp::cuda

namespace fp {
/// The GPU backend for a pass's run template (PerPixel.h).
struct CudaPixels {
    template <int N, class F>
    std::array<uint64_t, N> forEach(int width, int height, const F& fn, const char* what) const {
        return cuda::forEachPixel<N>(width, height, fn, what);
    }
};
}  // namespace fp
