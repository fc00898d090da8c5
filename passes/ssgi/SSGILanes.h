#pragma once
// SSGI on the CPU with a pixel's rays in SIMD lanes (the widest x86 instruction set the CPU has,
// chosen at run time): the kernel's own ssgiPixel over float lanes (foundation/LaneFloat.h),
// whose outputs are the scalar reference's bits (SSGITests checks it on every instruction set).
// SSGIPass::execute uses it unless `ssgi.lanes` is off.
#include "passes/ssgi/SSGIKernel.h"

#include <array>
#include <cstdint>
#include <vector>

namespace fp::ssgi {

/// Traces every pixel of the frame (one ssgiPixel's outputs each) on the CPU's thread pool, a
/// pixel's rays a vector at a time; returns the work counted (indexed by Counter).
std::array<uint64_t, kCounterCount> traceInLanes(const Frame& f);

/// The instruction set the lanes run on here and how many rays one vector holds ("AVX2", 8).
struct LaneTarget {
    const char* name;
    int lanes;
};
LaneTarget laneTarget();

}  // namespace fp::ssgi
