// HybridMarch.h: compiled once per x86 instruction set (foreach_target.h re-includes this file);
// recordTileMarch calls the widest one the CPU has. Each build is SSGI's own ssgiPixel over
// LaneFloat<the target's float lanes> (a pixel's rays a vector at a time: 4 with SSE4, 8 with
// AVX2, 16 with AVX-512) with the recording fallback, inlined whole but for the fallback's calls
// (flatten); every lane does the scalar kernel's arithmetic, one IEEE operation for one, and the
// fallback hears of the rays lane by lane in ray order (HybridTests checks the hybrid's bits on
// every instruction set).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/hybrid/HybridLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "passes/hybrid/HybridMarch.h"

HWY_BEFORE_NAMESPACE();
namespace fp::hybrid::HWY_NAMESPACE {

// One lane type per target (lanesForTarget).
constexpr int kLanesHere = lanesForTarget(int(HWY_LANES(float)));
using T = LaneFloat<kLanesHere>;

__attribute__((flatten)) void recordPixel(const ssgi::Frame& f, int x, int y,
                                          unsigned long long* counts,
                                          const RecordingFallback& record) {
    ssgi::ssgiPixel<T>(f, x, y, counts, record);
}

void recordHere(const ssgi::Frame& f, const Tile& t, const EmbreeFallback& fallback,
                TileMarch& march, unsigned long long* counts) {
    const RecordingFallback record{fallback, &march};
    for (int y = t.y0; y < t.y1; ++y)
        for (int x = t.x0; x < t.x1; ++x) recordPixel(f, x, y, counts, record);
}

}  // namespace fp::hybrid::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::hybrid {

HWY_EXPORT(recordHere);

void recordTileMarch(const ssgi::Frame& f, const Tile& t, const EmbreeFallback& fallback,
                     TileMarch& march, unsigned long long* counts) {
    march.pixels.clear();
    march.rays.clear();
    march.misses.clear();
    march.continuationHits.clear();
    HWY_DYNAMIC_DISPATCH(recordHere)(f, t, fallback, march, counts);
    march.pixels.push_back({0, 0, march.rays.size(), march.misses.size(),
                            march.continuationHits.size(), {}, {}});
}

}  // namespace fp::hybrid
#endif
