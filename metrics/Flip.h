#pragma once
// FLIP, NVIDIA's perceptual difference of a test image against a reference as one sees them
// flipped back and forth (Andersson et al., "FLIP: A Difference Evaluator for Alternating Images",
// HPG 2020), and its HDR form (Andersson et al., "Visualizing Errors in Rendered High Dynamic Range
// Images", Eurographics 2021 short papers): a per-pixel error in [0, 1] and its mean. docs/compare
// (docs/commands.md, "compare") gives every step and constant; in short:
//   colour: sRGB → YCxCz, each channel blurred by the eye's contrast sensitivity at the viewing
//     distance (sums of Gaussians), back to linear RGB clamped to the unit cube, then L*a*b* with
//     the Hunt adjustment (a, b scaled by L/100); HyAB distance |ΔL| + ‖(Δa, Δb)‖, raised to 0.7
//     and mapped to [0, 1] (the first 40 % of the largest distance, green to blue, onto [0, 0.95]);
//   features: edges and points of the luminance (first and second derivatives of a Gaussian of
//     0.082° peak to trough), their magnitudes' largest difference, scaled by 1/√2 and raised to
//     0.5;
//   the error: colour^(1 − features).
// HDR-FLIP: both images exposed at N exposures from the one that maps the reference's brightest
// luminance to 0.85 to the one that maps its median there, each tone mapped (ACES, Narkowicz's fit)
// and sRGB-encoded, LDR-FLIP taken at each; a pixel's error is its largest.
#include "foundation/Image.h"

#include <cstdint>

namespace fp {

/// Pixels per degree of visual angle seen on a 0.7 m wide 3840-pixel monitor from 0.7 m, FLIP's
/// default observer: 3840 / 0.7 m × 0.7 m × π / 180.
inline constexpr double kFlipDefaultPixelsPerDegree = 3840.0 * 3.14159265358979323846 / 180.0;

struct FlipOptions {
    double pixelsPerDegree = kFlipDefaultPixelsPerDegree;
    /// HDR-FLIP (linear radiance, exposures from the reference) or LDR-FLIP (sRGB-encoded values in
    /// [0, 1], a display's picture).
    bool hdr = true;
    /// HDR-FLIP's exposures; both 0 with `exposures` 0: from the reference, as above.
    double startExposure = 0, stopExposure = 0;
    int exposures = 0;
};

struct FlipResult {
    double mean = 0;         //!< over the pixels the mask keeps
    uint64_t pixels = 0;     //!< pixels measured
    uint64_t nonFinitePixels = 0;  //!< NaN or infinity in either image: error 1 there
    bool hdr = true;
    double startExposure = 0, stopExposure = 0;  //!< HDR-FLIP's range, in stops
    int exposures = 1;
};

/// FLIP of `test` against `reference` (the same size, 1, 3 or 4 channels: one is grey, a fourth
/// is left out), over the pixels where `mask`'s first channel is > 0 (null: every pixel); the
/// images are filtered whole either way, as one sees them. `errorMap`, when not null, receives
/// the per-pixel error (0 outside the mask). Throws fp::UsageError for other shapes.
FlipResult flip(const Image& reference, const Image& test, const Image* mask,
                const FlipOptions& options, Image* errorMap = nullptr);

}  // namespace fp
