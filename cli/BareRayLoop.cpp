#include "cli/BareRayLoop.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>

namespace fp::cli {

double timeBareOcclusion(const RayScene& scene, const std::vector<Ray>& rays, bool packets,
                         uint64_t& blocked) {
    const std::size_t packetCount = (rays.size() + kPacketSize - 1) / kPacketSize;
    const auto start = std::chrono::steady_clock::now();
    blocked = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, packetCount, 64), uint64_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, uint64_t sum) {
            Ray packet[kPacketSize];
            bool active[kPacketSize], hit[kPacketSize];
            for (std::size_t p = r.begin(); p != r.end(); ++p) {
                const std::size_t first = p * kPacketSize;
                const int n = int(std::min<std::size_t>(kPacketSize, rays.size() - first));
                if (packets) {
                    for (int i = 0; i < kPacketSize; ++i) {
                        active[i] = i < n;
                        packet[i] = rays[first + std::min(i, n - 1)];
                    }
                    scene.occluded8(packet, active, hit);
                    for (int i = 0; i < n; ++i) sum += hit[i];
                } else {
                    for (int i = 0; i < n; ++i) {
                        const Ray& q = rays[first + i];
                        sum += scene.occluded(q.org, q.dir, q.tnear, q.tfar);
                    }
                }
            }
            return sum;
        },
        [](uint64_t a, uint64_t b) { return a + b; });
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace fp::cli
