// The bare GPU traversal (Cuda.h's timeBareTraversal): rt_shadows' rays through the scene's BVH
// with nothing else per ray, the yardstick the pass's rays/s are compared with.
#include "foundation/Bvh.h"
#include "foundation/Cuda.h"
#include "foundation/RayScene.h"

#include <cuda_runtime.h>

#include <algorithm>
#include <vector>

namespace fp::cuda {

namespace {
__global__ void __launch_bounds__(128, 8)
    bareTraversal(const BvhView bvh, const Ray* rays, int count, bool closestHits,
                  unsigned long long* blocked) {
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= count) return;
    const Ray r = rays[i];
    // The pass's query (traceBlocker): the closest blocker where its distance is asked.
    const bool hit = traceBlocker(bvh, r.org, r.dir, r.tnear, r.tfar, closestHits) >= 0.0f;
    // One atomic per warp keeps the count from costing what it measures.
    const unsigned votes = __ballot_sync(__activemask(), hit);
    if ((threadIdx.x & 31) == __ffs(__activemask()) - 1 && votes)
        atomicAdd(blocked, (unsigned long long)__popc(votes));
}
}  // namespace

double timeBareTraversal(const BvhView& bvh, const std::vector<Ray>& rays, bool closestHits,
                         int runs, uint64_t& blocked) {
    blocked = 0;
    if (rays.empty()) return 0.0;
    const auto deviceRays = uploadBytes(rays.data(), rays.size() * sizeof(Ray));
    unsigned long long* counter = counterBuffer(1);
    std::vector<double> seconds;
    for (int run = 0; run < std::max(runs, 1); ++run) {
        checkStatus(cudaMemset(counter, 0, sizeof *counter), "bare traversal");
        EventTimer timer;
        timer.start();
        const int block = 128;
        bareTraversal<<<unsigned((rays.size() + block - 1) / block), block>>>(
            bvh, static_cast<const Ray*>(deviceRays.get()), int(rays.size()), closestHits, counter);
        checkStatus(cudaGetLastError(), "bare traversal");
        timer.stop();
        seconds.push_back(timer.seconds());
    }
    unsigned long long host = 0;
    checkStatus(cudaMemcpy(&host, counter, sizeof host, cudaMemcpyDeviceToHost), "bare traversal");
    blocked = host;
    std::sort(seconds.begin(), seconds.end());
    return seconds[seconds.size() / 2];
}

}  // namespace fp::cuda
