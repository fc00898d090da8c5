#pragma once
// Which pixels error_measure measures, one definition for its CPU loop and its CUDA kernel.
#include "foundation/PlaneView.h"
#include "metrics/ErrorMetrics.h"

namespace fp {

struct ErrorMask {
    PlaneView depth;      //!< none: no pixel is sky
    PlaneView roughness;  //!< none: no roughness cutoff
    PlaneView exclude;    //!< none: nothing excluded
    float skyDepth = 0, maxRoughness = 0, excludeAbove = 0;

    /// Whether any pixel can be left out (else the measure needs no mask).
    bool any() const { return depth.data || roughness.data || exclude.data; }
    /// 1: measured; 0: sky, rougher than the cutoff, or excluded.
    FP_HD float at(int x, int y) const {
        if (depth.data && isNotSky(depth.at(x, y), skyDepth) == 0.0f) return 0.0f;
        if (roughness.data && !(roughness.at(x, y) <= maxRoughness)) return 0.0f;
        if (exclude.data && !(exclude.at(x, y) <= excludeAbove)) return 0.0f;
        return 1.0f;
    }
};

}  // namespace fp
