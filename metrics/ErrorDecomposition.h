#pragma once
// The error of a result taken apart along a ladder of images that ends at its reference:
// result → same pass converged → screen-space oracle → one-bounce truth → full truth, say. Each
// rung is compared with the next; with N the (pixel, channel) values in the mask, e = result −
// reference the total difference and d_k = rung k − rung k+1 (so e = Σ d_k):
//   step RMSE   √(Σ d_k²/N)     step bias   Σ d_k/N          (the biases add up to Σ e/N)
//   share       Σ d_k·e / Σ e²  (the shares add up to 1)
// RMSEs do not add, but squared error does along e: Σ e² = Σ_k Σ d_k·e. A step's share is the
// part of the total squared error that lies along that step; it is negative when the step
// cancels part of the others (a step that overshoots in the direction opposite to the total).
#include "foundation/Image.h"

#include <cstdint>
#include <vector>

namespace fp {

struct LadderRung {
    const Image* image = nullptr;
    /// At half the reference's resolution: read point-upsampled, as error_measure reads it.
    bool halfResolution = false;
};

struct DecompositionStep {
    double rmse = 0, bias = 0, share = 0;
};

struct ErrorDecompositionStats {
    uint64_t values = 0;  //!< (pixel, channel) values inside the mask
    double rmse = 0, bias = 0;  //!< of the first rung against the last
    std::vector<DecompositionStep> steps;  //!< rung k against rung k+1
};

/// Takes the error of ladder.front() against ladder.back() apart (at least two rungs, all with
/// the reference's channel count, the reference's size or half of it). `mask`: 1 channel of the
/// reference's size, > 0 = compare this pixel; null = all. Throws fp::Error when the rungs do not
/// fit together.
ErrorDecompositionStats decomposeError(const std::vector<LadderRung>& ladder, const Image* mask);

}  // namespace fp
