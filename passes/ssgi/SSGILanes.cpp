// SSGILanes.h: compiled once per x86 instruction set (foreach_target.h re-includes this file);
// traceInLanes calls the widest one the CPU has. Each build is the kernel's own ssgiPixel over
// LaneFloat<the target's float lanes> (a pixel's rays a vector at a time: 4 with SSE4, 8 with
// AVX2, 16 with AVX-512), inlined whole (flatten) so it compiles to that instruction set; every
// lane does the scalar reference's arithmetic, one IEEE operation for one (SSGIKernel.h).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/ssgi/SSGILanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "foundation/PerPixel.h"
#include "passes/ssgi/SSGILanes.h"
#include "passes/ssgi/SSGIPass.h"

HWY_BEFORE_NAMESPACE();
namespace fp::ssgi::HWY_NAMESPACE {

// One lane type per target (lanesForTarget).
constexpr int kLanesHere = lanesForTarget(int(HWY_LANES(float)));
using T = LaneFloat<kLanesHere>;

__attribute__((flatten)) void tracePixel(const Frame& f, int x, int y, unsigned long long* counts) {
    ssgiPixel<T>(f, x, y, counts);
}

std::array<uint64_t, kCounterCount> traceFrame(const Frame& f) {
    FP_CHECK(f.setup.rays >= 1 && f.setup.rays <= SSGIPass::kMaxRays,
             "SSGI traces 1 to {} rays, not {}", SSGIPass::kMaxRays, f.setup.rays);
    return CpuPixels{}.forEach<kCounterCount>(
        f.ao.width, f.ao.height,
        [&](int x, int y, WorkCounts<kCounterCount>& c) { tracePixel(f, x, y, c.value); }, "ssgi");
}

LaneTarget target() {
    return {hwy::TargetName(HWY_TARGET), kLanesHere};
}

}  // namespace fp::ssgi::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::ssgi {

HWY_EXPORT(traceFrame);
HWY_EXPORT(target);

std::array<uint64_t, kCounterCount> traceInLanes(const Frame& f) {
    return HWY_DYNAMIC_DISPATCH(traceFrame)(f);
}

LaneTarget laneTarget() {
    return HWY_DYNAMIC_DISPATCH(target)();
}

}  // namespace fp::ssgi
#endif
