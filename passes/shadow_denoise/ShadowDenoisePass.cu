// ShadowDenoisePass on the GPU: shadow_denoise::run with device images, one thread per pixel (per
// row and per column for the occluder table).
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/shadow_denoise/ShadowDenoiseKernel.h"
#include "passes/shadow_denoise/ShadowDenoisePass.h"
#include "shading/NamedLight.h"

namespace fp {

namespace shadow_denoise {

namespace {
// One warp a row: each lane counts one of 32 neighbouring pixels, a warp scan sums them, the
// row's running total carries to the next 32.
__global__ void occluderRows(const __grid_constant__ Frame f) {
    const int y = int((blockIdx.x * blockDim.x + threadIdx.x) / 32), lane = int(threadIdx.x & 31);
    if (y >= f.height) return;
    const OccluderCounts& o = f.occluders;
    if (y == 0)
        for (int x = lane; x <= f.width; x += 32) o.at(x, 0) = 0;
    if (lane == 0) o.at(0, y + 1) = 0;
    uint32_t carry = 0;
    for (int base = 0; base < f.width; base += 32) {
        const int x = base + lane;
        uint32_t v = x < f.width && f.hits.at(x, y) >= 0.0f && f.surfaces.at(x, y).valid ? 1u : 0u;
        for (int d = 1; d < 32; d *= 2) {
            const uint32_t n = __shfl_up_sync(0xffffffffu, v, d);
            if (lane >= d) v += n;
        }
        if (x < f.width) o.at(x + 1, y + 1) = carry + v;
        carry += __shfl_sync(0xffffffffu, v, 31);
    }
}

// 32 columns a block, their rows 1…H in 32 segments: each thread sums its segment, then adds the
// segments above its own and writes its segment's running sums.
__global__ void occluderColumns(const __grid_constant__ Frame f) {
    __shared__ uint32_t segment[32][33];
    const int x = int(blockIdx.x * 32 + threadIdx.x);
    const int rows = (f.height + 31) / 32;
    const int y0 = 1 + int(threadIdx.y) * rows, y1 = y0 + rows < f.height + 1 ? y0 + rows : f.height + 1;
    const OccluderCounts& o = f.occluders;
    uint32_t sum = 0;
    if (x <= f.width)
        for (int y = y0; y < y1; ++y) sum += o.at(x, y);
    segment[threadIdx.y][threadIdx.x] = sum;
    __syncthreads();
    uint32_t running = 0;
    for (int k = 0; k < int(threadIdx.y); ++k) running += segment[k][threadIdx.x];
    if (x <= f.width)
        for (int y = y0; y < y1; ++y) {
            running += o.at(x, y);
            o.at(x, y) = running;
        }
}
}  // namespace

void buildOccluderTable(const Frame& f, const CudaPixels&) {
    occluderRows<<<unsigned((f.height * 32 + 127) / 128), 128>>>(f);
    cuda::checkStatus(cudaGetLastError(), "shadow_denoise rows");
    occluderColumns<<<unsigned((f.width + 1 + 31) / 32), dim3(32, 32)>>>(f);
    cuda::checkStatus(cudaGetLastError(), "shadow_denoise columns");
}

}  // namespace shadow_denoise

void ShadowDenoisePass::executeCuda(PassContext& ctx) {
    shadow_denoise::run(ctx, DevicePorts{ctx}, CudaPixels{}, namedLight(ctx.lights(), mParams.light),
                        mParams.denoiser, mParams.reconstructionSamples, mParams.preConvolution,
                        mParams.maxRadius);
}

}  // namespace fp
