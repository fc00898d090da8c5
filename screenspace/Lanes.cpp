#include "screenspace/Lanes.h"

#include <hwy/targets.h>

namespace fp {

std::vector<int64_t> laneTargetsHere() {
    return hwy::SupportedAndGeneratedTargets();
}

void useOnlyLaneTarget(int64_t target) {
    hwy::SetSupportedTargetsForTest(target);
}

}  // namespace fp
