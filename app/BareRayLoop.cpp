#include "app/BareRayLoop.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>

namespace fp::app {

double timeBareOcclusion(const RayScene& scene, const std::vector<Ray>& rays, int width,
                         bool closestHits, uint64_t& blocked) {
    // The rays as the pass hands them to Embree, a structure of arrays, laid out before the clock
    // starts.
    std::vector<float> soa[7];
    for (auto& a : soa) a.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Ray& q = rays[i];
        const float v[7] = {q.org.x, q.org.y, q.org.z, q.dir.x, q.dir.y, q.dir.z, q.tfar};
        for (int k = 0; k < 7; ++k) soa[k][i] = v[k];
    }
    const RayArrays all{soa[0].data(), soa[1].data(), soa[2].data(), soa[3].data(),
                        soa[4].data(), soa[5].data(), soa[6].data()};
    const std::size_t packetCount = (rays.size() + width - 1) / width;
    const auto start = std::chrono::steady_clock::now();
    blocked = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, packetCount, 64), uint64_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, uint64_t sum) {
            bool hit[kMaxPacketSize];
            float t[kMaxPacketSize];
            for (std::size_t p = r.begin(); p != r.end(); ++p) {
                const std::size_t first = p * std::size_t(width);
                const int n = int(std::min<std::size_t>(std::size_t(width), rays.size() - first));
                const RayArrays packet = all.from(first);
                if (width > 1) {
                    scene.occludedWithDistancePacket(packet, n, width, hit,
                                                     closestHits ? t : nullptr);
                    for (int i = 0; i < n; ++i) sum += hit[i];
                } else {
                    for (int i = 0; i < n; ++i) {
                        const Ray q = packet.at(i);
                        sum += scene.occluded(q.org, q.dir, q.tnear, q.tfar);
                    }
                }
            }
            return sum;
        },
        [](uint64_t a, uint64_t b) { return a + b; });
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double timeBareClosestHit(const RayScene& scene, const std::vector<Ray>& rays, int width,
                          uint64_t& hits) {
    const std::size_t step = std::size_t(width);
    const std::size_t packetCount = (rays.size() + step - 1) / step;
    const auto start = std::chrono::steady_clock::now();
    hits = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, packetCount, width > 1 ? 64 : 1024), uint64_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, uint64_t sum) {
            RayHit hit[kMaxPacketSize];
            for (std::size_t p = r.begin(); p != r.end(); ++p) {
                const std::size_t first = p * step;
                const int n = int(std::min(step, rays.size() - first));
                if (width > 1) {
                    scene.intersectPacket(rays.data() + first, n, width, hit);
                    for (int i = 0; i < n; ++i) sum += hit[i].hit;
                } else {
                    const Ray& q = rays[first];
                    sum += scene.intersect(q.org, q.dir, q.tnear, q.tfar).hit;
                }
            }
            return sum;
        },
        [](uint64_t a, uint64_t b) { return a + b; });
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace fp::app
