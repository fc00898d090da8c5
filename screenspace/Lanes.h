#pragma once
// What the SIMD-lane code (the *Lanes.cpp of ssgi, deferred_lighting, rt_shadows and
// rt_ambient_occlusion, and shading/DiffusePathLanes.cpp) shares outside Highway's per-target code: which instruction sets they can
// run on here, and a switch for the tests that check each one against the scalar reference bit
// for bit.
#include <cstdint>
#include <vector>

namespace fp {

/// The instruction sets this build has lanes for that this CPU runs (Highway target bits).
std::vector<int64_t> laneTargetsHere();
/// Makes every lane pass use only `target` (0: the widest this CPU has, again). Tests only.
void useOnlyLaneTarget(int64_t target);

}  // namespace fp
