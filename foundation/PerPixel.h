#pragma once
// How a pass runs its per-pixel function on either backend. A pass writes its work once, as a
// template over a Ports type (PassPorts.h) and a Pixels type — CpuPixels here, CudaPixels in
// CudaLaunch.cuh — calling `pixels.forEach<N>(w, h, fn)` with fn an FP_HD lambda
// (int x, int y, WorkCounts<N>& counts); N = 0 when the loop counts nothing (the GPU then need
// not wait for it). execute() instantiates it with (HostPorts, CpuPixels),
// the pass's .cu file with (DevicePorts, CudaPixels): the same code, the same arithmetic.
#include "foundation/HostDevice.h"
#include "foundation/Tiles.h"

#include <array>
#include <atomic>
#include <cstdint>

namespace fp {

/// Adds `v` to a counter every pixel shares — a pass's counts that its per-pixel function cannot
/// return through WorkCounts (a callable's inside another pass's kernel): an atomic add on
/// either backend, so any order gives the same total.
FP_HD inline void addSharedCount(unsigned long long* counter, unsigned long long v) {
#if defined(__CUDA_ARCH__)
    atomicAdd(counter, v);
#else
    std::atomic_ref<unsigned long long>(*counter).fetch_add(v, std::memory_order_relaxed);
#endif
}

/// The GPU's Pixels (CudaLaunch.cuh), named here for the rare pass that gives it its own code.
struct CudaPixels;

/// Per-pixel work counters ("pixels", "rays", …), N fixed by the pass.
template <int N>
struct WorkCounts {
    unsigned long long value[N > 0 ? N : 1];
};

/// The CPU: tiles on the shared oneTBB pool (Tiles.h), counters summed per tile.
struct CpuPixels {
    template <int N, class F>
    std::array<uint64_t, N> forEach(int width, int height, F fn, const char* /*what*/) const {
        std::array<std::atomic<uint64_t>, N> totals{};
        forEachTile(width, height, [&](const Tile& t) {
            WorkCounts<N> counts{};
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x)
                    fn(x, y, counts);
            for (int i = 0; i < N; ++i)
                totals[i] += counts.value[i];
        });
        std::array<uint64_t, N> result{};
        for (int i = 0; i < N; ++i)
            result[i] = totals[i];
        return result;
    }
};

}  // namespace fp
