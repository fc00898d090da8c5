#pragma once
// compare's work: the error of image A against reference B (an EXR layer, one channel of it, a
// product of layers, a buffer a capture profile maps, or a picture), over the pixels the masks
// keep, with the reference's own noise where B carries a .StdErr layer, and a heat map.
#include "metrics/ErrorMetrics.h"
#include "metrics/Flip.h"

#include <nlohmann/json.hpp>

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace fp::app {

struct CompareOptions {
    std::string a, b;          //!< the result and the reference (files)
    std::string layer;         //!< what to compare in A (and B); "" = the layer both have
    std::string refLayer;      //!< in B, when named differently
    std::string heatmap;       //!< write |A−B| here (EXR, plus a .png preview); "" = none
    std::string ocioConfig;    //!< for the preview ("" = $OCIO, then framepass's own)
    std::string profile = "canonical", refProfile;  //!< capture profiles of A and B
    std::vector<std::string> masks = {"sky"};        //!< sky, none, shading-model=N, id=N, picture
    double tolerance = 0.1;
    double skyDistance = std::numeric_limits<double>::infinity();
    double heatMax = 0;  //!< the colour map's top (0 = the 99th percentile)
    std::string maxMemory;  //!< refuse when the forecast is over this ("" = the default limit)
    /// FLIP beside the figures: "auto" (LDR-FLIP when A is a picture, display-referred, else
    /// HDR-FLIP), "hdr", "ldr" or "off"; for images of 1, 3 or 4 channels.
    std::string flip = "auto";
    double pixelsPerDegree = kFlipDefaultPixelsPerDegree;  //!< FLIP's observer
    double maxRmse = -1;  //!< the CLI's --max-rmse (not used here)
    bool json = false;    //!< the CLI's --json (not used here)
};

struct CompareResult {
    ErrorStats stats;
    std::string layerA, layerB;  //!< as resolved
    std::string maskNote;        //!< which pixels counted, in words
    float heatScale = 0;         //!< top of the heat map's colour map (with a heat map)
    std::optional<FlipResult> flip;  //!< FLIP, where it was taken (CompareOptions::flip)
    /// The two layers were made to measure different things (their files record truths of
    /// different definitions: an AO radius, bounces; app/TruthDefinitions.h). Also logged.
    std::vector<std::string> warnings;
    /// What `compare --json` prints.
    nlohmann::json toJson(const CompareOptions& options) const;
};

/// Reads both, measures, writes the heat map if asked. Throws fp::UsageError for what cannot be
/// compared (channels, sizes, a missing layer), naming it.
CompareResult compareFiles(const CompareOptions& options);

/// compare's measurement on images already in memory (the Python module's arrays): the figures
/// of `a` against reference `b` over the pixels `mask` keeps (first channel > 0; null = all),
/// with the reference's noise where `referenceStdErr` is given, and |a − b| into `absError` when
/// not null. Throws fp::UsageError naming `nameA` and `nameB` when the channels or sizes differ.
ErrorStats compareImages(const Image& a, const Image& b, const Image* mask,
                         const Image* referenceStdErr, double tolerance,
                         const std::string& nameA = "a", const std::string& nameB = "b",
                         Image* absError = nullptr);

/// FLIP of `a` against reference `b` over the pixels `mask` keeps, as compare takes it: `mode`
/// "auto" (LDR-FLIP when `displayReferred`, else HDR-FLIP), "hdr", "ldr" or "off"; nullopt when
/// off or when the images have other than 1, 3 or 4 channels (FLIP compares colours). The
/// per-pixel error goes to `map` when given and taken. Throws fp::UsageError for another mode or
/// a pixels-per-degree that is not a positive number.
std::optional<FlipResult> compareFlip(const Image& a, const Image& b, const Image* mask,
                                      const std::string& mode, bool displayReferred,
                                      double pixelsPerDegree, Image* map = nullptr);
/// `flip` into compare's figures: "flip" (the mean) and "flipSettings" (how it was taken), or
/// "flip": null when it was not.
void addFlipFigures(nlohmann::json& figures, const std::optional<FlipResult>& flip,
                    double pixelsPerDegree);

/// The heat map's PNG preview beside its EXR.
std::string heatmapPngPath(const std::string& exr);

}  // namespace fp::app
