#pragma once
// Error of an image against a reference, over the pixels that matter (DESIGN §6). With N the
// number of (pixel, channel) values in the mask, e = a − b and ε = 0.01 (the usual guard of
// relative metrics against dark pixels):
//   RMSE   √(Σe²/N)            relMSE  Σ e²/(b² + ε) / N        SMAPE  Σ 2|e|/(|a| + |b|) / N
//   MAE    Σ|e|/N              bias    Σe/N                     max    max|e|
//   overTolerance  fraction of pixels whose largest |e| exceeds tolerance·(|b| + ε)
// When the reference carries its standard error σ (a Truth.*.StdErr layer), `noiseRmse` =
// √(Σσ²/N) is the RMSE that a perfect result would still show against this reference: the floor
// below which a comparison says nothing.
#include "passes/core/Image.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace fp {

inline constexpr double kRelativeEpsilon = 0.01;

struct ErrorStats {
    uint64_t pixels = 0;         //!< pixels compared (inside the mask)
    uint64_t maskedPixels = 0;   //!< pixels left out (sky)
    double rmse = 0, relMse = 0, smape = 0, mae = 0, bias = 0, maxError = 0;
    double overTolerance = 0;
    double tolerance = 0;
    std::optional<double> noiseRmse;  //!< the reference's own noise, when known

    /// True when the measured error is within twice the reference's noise.
    bool noiseLimited() const { return noiseRmse && rmse <= 2.0 * *noiseRmse; }
    /// The figures by name (rmse, relMse, ..., referenceNoiseRmse when known): what compare's
    /// JSON and error_measure's report share.
    std::map<std::string, double> figures() const;
    nlohmann::json toJson() const;
};

struct ErrorInputs {
    const Image* result = nullptr;     //!< a
    const Image* reference = nullptr;  //!< b, same size and channel count
    const Image* referenceStdErr = nullptr;  //!< σ of b, optional
    const Image* mask = nullptr;       //!< 1 channel, > 0 = compare this pixel; null = all
    double tolerance = 0.1;
};

/// Computes the statistics; if `absError` is given it receives the per-pixel mean |e| over the
/// channels (0 outside the mask), same size, 1 channel.
ErrorStats measureError(const ErrorInputs& in, Image* absError = nullptr);

/// Mask of the pixels that are not sky: finite depth below `skyDistance`.
Image notSkyMask(const Image& sceneDepth, float skyDistance);

/// Median over the pixels of the mask with a non-zero mean of ‖σ‖/‖mean‖ (L2 over channels):
/// how noisy a truth layer is, relative to its value. NaN when no pixel qualifies.
double medianRelativeStdErr(const Image& mean, const Image& stdErr, const Image* mask = nullptr);

}  // namespace fp
