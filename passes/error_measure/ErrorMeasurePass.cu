// ErrorMeasurePass on the GPU. Each pixel's terms and |error| are the CPU's (measurePixel, the
// same double arithmetic); only the order of the sums differs: each row is summed by one warp, 32
// lanes striding along it and the lanes added in lane order, and the rows are added on the host
// in row order — deterministic from run to run, and within a few double roundings of the CPU's
// tile-order sums. The heat map's 99th percentile is selected exactly, by radix selection over the
// float bits of |error| (4 rounds of 256-bin histograms).
#include "screenspace/GBuffer.h"
#include "foundation/Cuda.h"
#include "foundation/CudaLaunch.cuh"
#include "foundation/Error.h"
#include "passes/error_measure/ErrorMeasurePass.h"
#include "metrics/ErrorMetrics.h"
#include "metrics/Heatmap.h"

#include <cuda_runtime.h>

#include <bit>
#include <cmath>
#include <limits>
#include <vector>

namespace fp {

namespace {

constexpr int kRowsPerBlock = 4;  // one warp per row

__global__ void __launch_bounds__(32 * kRowsPerBlock)
    sumRows(const __grid_constant__ ErrorPixelInputs in, int width, int height, PlaneSpan absError,
            ErrorSums* rowSums) {
    __shared__ ErrorSums lanes[kRowsPerBlock][32];
    const int lane = threadIdx.x, row = threadIdx.y;
    const int y = blockIdx.x * kRowsPerBlock + row;
    ErrorSums sum;
    if (y < height)
        for (int x = lane; x < width; x += 32) {
            const float e = measurePixel(in, x, y, sum);
            if (absError)
                absError.at(x, y) = e;
        }
    lanes[row][lane] = sum;
    __syncthreads();
    if (lane == 0 && y < height) {
        ErrorSums total = lanes[row][0];
        for (int i = 1; i < 32; ++i)
            total.add(lanes[row][i]);
        rowSums[y] = total;
    }
}

// Histogram of byte `shift` of the bits of the masked-in |error| values whose higher bytes equal
// `prefix` (non-negative floats order as their bits do).
__global__ void byteHistogram(PlaneView absError, PlaneView mask, uint32_t prefix, uint32_t highMask,
                              int shift, unsigned int* bins) {
    __shared__ unsigned int local[256];
    const int lane = threadIdx.y * blockDim.x + threadIdx.x;
    for (int i = lane; i < 256; i += blockDim.x * blockDim.y)
        local[i] = 0;
    __syncthreads();
    const int x = blockIdx.x * blockDim.x + threadIdx.x;
    const int y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x < absError.width && y < absError.height && (!mask.data || mask.at(x, y) > 0.0f)) {
        const uint32_t bits = std::bit_cast<uint32_t>(absError.at(x, y));
        if ((bits & highMask) == prefix)
            atomicAdd(&local[(bits >> shift) & 0xFFu], 1u);
    }
    __syncthreads();
    for (int i = lane; i < 256; i += blockDim.x * blockDim.y)
        if (local[i])
            atomicAdd(&bins[i], local[i]);
}

// The value of rank `k` (0-based, ascending) among the masked-in |error| values: what
// heatScale's nth_element picks on the CPU.
float selectRank(PlaneView absError, PlaneView mask, unsigned long long k) {
    auto bins = std::static_pointer_cast<unsigned int>(cuda::allocateBytes(256 * sizeof(unsigned)));
    uint32_t prefix = 0, highMask = 0;
    const dim3 block(16, 8);
    const dim3 grid((absError.width + 15) / 16, (absError.height + 7) / 8);
    for (int shift = 24; shift >= 0; shift -= 8) {
        cuda::checkStatus(cudaMemsetAsync(bins.get(), 0, 256 * sizeof(unsigned)), "error_measure");
        byteHistogram<<<grid, block>>>(absError, mask, prefix, highMask, shift, bins.get());
        cuda::checkStatus(cudaGetLastError(), "error_measure");
        unsigned int host[256];
        cuda::checkStatus(cudaMemcpy(host, bins.get(), sizeof host, cudaMemcpyDeviceToHost),
                          "error_measure");
        uint32_t byte = 0;
        for (; byte < 255 && k >= host[byte]; ++byte)
            k -= host[byte];
        prefix |= byte << shift;
        highMask |= 0xFFu << shift;
    }
    return std::bit_cast<float>(prefix);
}

}  // namespace

void ErrorMeasurePass::executeCuda(PassContext& ctx) {
    const DeviceImage& b = ctx.deviceInput(kReference)->image();
    const DeviceImage& a = ctx.deviceInput(kSource)->image();
    const DeviceTexture* sigma = ctx.deviceInput(kReferenceStdErr);
    const DeviceTexture* depth = ctx.deviceInput(gbuffer::kDepth);
    const int W = b.width(), H = b.height();
    ErrorPixelInputs in =
        errorPixelInputs(a, b, sigma ? &sigma->image() : nullptr, mParams.tolerance,
                         isHalfResolution({a.width(), a.height()}, {W, H}));
    const DeviceTexture* roughness = mParams.maxRoughness > 0.0f ? ctx.deviceInput(kRoughness) : nullptr;
    const DeviceTexture* exclude = ctx.deviceInput(kExclude);
    for (const auto& [port, t] : {std::pair{kRoughness, roughness}, std::pair{kExclude, exclude}})
        FP_CHECK(!t || (t->image().width() == W && t->image().height() == H),
                 "error_measure: input '{}' is {}×{}, the reference {}×{}", port,
                 t->image().width(), t->image().height(), W, H);
    ErrorMask select = maskThresholds();
    if (depth) select.depth = depth->image().plane(0);
    if (roughness) select.roughness = roughness->image().plane(0);
    if (exclude) select.exclude = exclude->image().plane(0);
    DeviceTexture mask;
    if (select.any()) {
        mask = cuda::allocate({{W, H}}, {"Y"});
        const PlaneSpan m = mask.image().plane(0);
        CudaPixels{}.forEach<0>(
            W, H, [=] FP_HD(int x, int y, WorkCounts<0>&) { m.at(x, y) = select.at(x, y); },
            "error_measure mask");
        in.mask = viewOf(m);
    }

    const bool wantHeat = ctx.isRequested(kHeat);
    DeviceTexture absError;
    if (ctx.isRequested(kAbsError))
        absError = ctx.deviceOutput(kAbsError, {{W, H}}, false);  // every pixel written
    else if (wantHeat)
        absError = cuda::allocate({{W, H}}, {"Y"});
    const PlaneSpan err = absError.empty() ? PlaneSpan{} : absError.image().plane(0);

    auto rowSums = std::static_pointer_cast<ErrorSums>(
        cuda::allocateBytes(sizeof(ErrorSums) * std::size_t(std::max(H, 1))));
    sumRows<<<(H + kRowsPerBlock - 1) / kRowsPerBlock, dim3(32, kRowsPerBlock)>>>(in, W, H, err,
                                                                                   rowSums.get());
    cuda::checkStatus(cudaGetLastError(), "error_measure");
    std::vector<ErrorSums> rows(H);
    cuda::checkStatus(cudaMemcpy(rows.data(), rowSums.get(), sizeof(ErrorSums) * H,
                                 cudaMemcpyDeviceToHost),
                      "error_measure");
    ErrorSums total;
    for (const ErrorSums& r : rows)
        total.add(r);
    const ErrorStats s = finishError(total, mParams.tolerance, sigma != nullptr);
    reportStats(ctx, s);

    if (wantHeat) {
        const float scale =
            mParams.heatScale > 0.0f
                ? mParams.heatScale
                : (s.pixels == 0 ? 0.0f
                                 : selectRank(viewOf(err), in.mask,
                                              std::min<unsigned long long>(
                                                  s.pixels - 1, (unsigned long long)(0.99 * double(s.pixels)))));
        DeviceImage& heat = ctx.deviceOutput(kHeat, {{W, H}}, false).image();  // every pixel written
        const PlaneSpan r = heat.plane(0), g = heat.plane(1), bl = heat.plane(2);
        const PlaneView mask = in.mask, e = viewOf(err);
        const float grey = heatMaskedGrey();
        CudaPixels{}.forEach<0>(
            W, H,
            [=] FP_HD(int x, int y, WorkCounts<0>&) {
                float rgb[3];
                heatPixel(e, mask, scale, grey, x, y, rgb);
                r.at(x, y) = rgb[0];
                g.at(x, y) = rgb[1];
                bl.at(x, y) = rgb[2];
            },
            "error_measure heat");
        ctx.addMetric("heatScale", scale);
    }
}

}  // namespace fp
