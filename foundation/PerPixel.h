#pragma once
// How a pass runs its per-pixel function on either backend. A pass writes its work once, as a
// template over a Ports type (PassPorts.h) and a Pixels type — CpuPixels here, CudaPixels in
// CudaLaunch.cuh — calling `pixels.forEach<N>(w, h, fn)` with fn an FP_HD lambda
// (int x, int y, WorkCounts<N>& counts); N = 0 when the loop counts nothing (the GPU then need
// not wait for it); or `pixels.forEachInSteps<N, State>(w, h, begin, step)` where a pixel's work
// is a loop of uneven length. execute() instantiates it with (HostPorts, CpuPixels),
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

/// forEachInSteps' pixel in one call: set up, then its steps one after another to the last.
template <int N, class State, class Begin, class Step>
struct StepsInOrder {
    Begin begin;
    Step step;
    FP_HD void operator()(int x, int y, WorkCounts<N>& counts) const {
        State state{};
        if (begin(x, y, state, counts))
            while (step(state, counts)) {
            }
    }
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

    /// Work a pixel does in a number of steps that differs from pixel to pixel (a ray-traced
    /// pass's paths, one ray a step): begin(x, y, State&, counts) sets pixel (x, y) up in a
    /// default-made State and says whether it has a step to take; step(State&, counts) takes one
    /// and says whether another follows. A pixel's steps run in order (StepsInOrder), so its bits
    /// do not depend on the backend or on how the backend interleaves pixels.
    template <int N, class State, class Begin, class Step>
    std::array<uint64_t, N> forEachInSteps(int width, int height, Begin begin, Step step,
                                           const char* what) const {
        return forEach<N>(width, height, StepsInOrder<N, State, Begin, Step>{begin, step}, what);
    }
};

}  // namespace fp
