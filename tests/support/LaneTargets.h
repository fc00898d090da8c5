#pragma once
// Tests of code that runs in SIMD lanes: the same check on every instruction set this CPU runs
// the lanes on (screenspace/Lanes.h), each the only one used while the check runs.
#include "screenspace/Lanes.h"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

namespace fp::test {

/// check() once for each instruction set of the lanes this CPU runs, with only that one used
/// (the widest again after it).
template <class Check>
void onEveryLaneTarget(Check&& check) {
    const std::vector<int64_t> targets = laneTargetsHere();
    REQUIRE(!targets.empty());
    for (int64_t target : targets) {
        INFO("target ", target);
        useOnlyLaneTarget(target);
        check();
        useOnlyLaneTarget(0);
    }
}

}  // namespace fp::test
