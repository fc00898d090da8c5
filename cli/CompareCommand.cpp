// framepass compare: error of one image against a reference (DESIGN §6), as numbers, JSON and a
// heat map.
#include "cli/Commands.h"
#include "cli/Invocation.h"
#include "io/CaptureFiles.h"
#include "io/CaptureSource.h"
#include "io/ContactSheet.h"
#include "io/ExrLayers.h"
#include "io/ExrWriter.h"
#include "io/PngWriter.h"
#include "io/SafeFiles.h"
#include "passes/core/Error.h"
#include "passes/core/SemanticBuffers.h"
#include "passes/display/DisplayTransform.h"
#include "passes/metrics/ErrorMetrics.h"
#include "passes/metrics/Heatmap.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <set>

namespace fp::cli {

namespace {

std::string displayName(const std::string& layer) { return layer.empty() ? "\"\"" : layer; }

// The one layer both files have (ignoring depth and standard errors), for when no --layer is
// given.
std::string commonLayer(const io::ExrReader& a, const io::ExrReader& b) {
    std::set<std::string> inB;
    for (const auto& l : io::listLayers(b)) inB.insert(l.name);
    std::vector<std::string> common, namesA;
    for (const auto& l : io::listLayers(a)) {
        namesA.push_back(displayName(l.name));
        const bool stdErr = l.name.size() > 7 && l.name.compare(l.name.size() - 7, 7, ".StdErr") == 0;
        const bool meta = l.name == "SceneDepth" || stdErr;
        if (inB.count(l.name) && !meta) common.push_back(l.name);
    }
    if (common.size() == 1) return common[0];
    throw UsageError(fmt::format("{} and {} share {} comparable layers; pick one with --layer "
                                 "(and --ref-layer if the reference names it differently). "
                                 "Layers of {}: {}",
                                 a.path(), b.path(), common.size(), a.path(), fmt::join(namesA, ", ")));
}

// `layer` of the file: through the profile when it maps a buffer of that name (so a Blender
// capture's SceneDepth is in scene units, with its sky), else the file's own layer.
Image readImage(io::ExrReader& file, const std::string& layer,
                const io::CaptureProfile& profile) {
    if (profile.mappings(layer)) {
        io::CaptureFiles files(file.path(), profile);
        if (files.mappingFor(layer)) {
            std::vector<std::string> notes;
            return files.read(layer, int(findSemanticBuffer(layer)->channels.size()), notes);
        }
    }
    return io::readLayer(file, io::findLayer(file, layer));
}

// The capture's SceneDepth as its profile reads it (scale, sky threshold, the depth file of a
// multi-file capture), or nothing when the file has none.
std::optional<Image> readDepth(const std::string& path, const io::CaptureProfile& profile) {
    std::optional<io::CaptureFiles> files;
    try {
        files.emplace(path, profile);
    } catch (const Error&) {
        return std::nullopt;  // not a capture of this profile (a result image, say)
    }
    if (!files->mappingFor("SceneDepth")) return std::nullopt;
    std::vector<std::string> notes;
    return files->read("SceneDepth", 1, notes);
}

std::string pngPathFor(const std::string& exr) {
    std::filesystem::path p(exr);
    return p.replace_extension(".png").string();
}

}  // namespace

Command addCompareCommand(CLI::App& app) {
    struct Options {
        std::string a, b, layer, refLayer, mask = "sky", heatmap, ocioConfig, profile = "canonical",
                    refProfile;
        double tolerance = 0.1, skyDistance = std::numeric_limits<double>::infinity();
        double heatMax = 0, maxRmse = -1;
        bool json = false;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand(
        "compare", "error of image A against reference B: RMSE, relMSE, SMAPE, MAE, bias, max, "
                   "fraction over tolerance, the reference's own noise, and a heat map");
    sub->add_option("a", opt->a, "result EXR")->required();
    sub->add_option("b", opt->b, "reference EXR (e.g. a capture with Truth.* layers)")->required();
    sub->add_option("--layer", opt->layer, "layer to compare (in A, and in B unless --ref-layer)");
    sub->add_option("--ref-layer", opt->refLayer, "layer of B, when it is named differently");
    sub->add_option("--mask", opt->mask, "sky: leave out pixels whose SceneDepth is sky; none")
        ->check(CLI::IsMember({"sky", "none"}));
    sub->add_option("--profile", opt->profile,
                    "capture profile (NAME or FILE.json, default canonical): a --layer that names "
                    "a buffer it maps (SceneDepth, WorldNormal, …) is read through it, and it "
                    "finds SceneDepth for the sky mask");
    sub->add_option("--ref-profile", opt->refProfile,
                    "capture profile of B when it differs from A's, e.g. a Blender capture "
                    "against framepass's own");
    sub->add_option("--sky-distance", opt->skyDistance,
                    "depths at or beyond this are sky (default: only +inf)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--tolerance", opt->tolerance,
                    "a pixel is over tolerance when |A−B| > T·(|B| + 0.01) (default 0.1)")
        ->check(CLI::NonNegativeNumber);
    sub->add_flag("--json", opt->json, "print the statistics as JSON");
    sub->add_option("--heatmap", opt->heatmap,
                    "write |A−B| as an EXR heat map here, plus a .png preview next to it");
    sub->add_option("--heat-max", opt->heatMax,
                    "error at the top of the colour map (default: the 99th percentile)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--max-rmse", opt->maxRmse, "exit with 1 when the RMSE is above this")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--ocio-config", opt->ocioConfig,
                    "OCIO config for the PNG preview (default $OCIO, then framepass's own)");

    return [opt]() {
        if (!opt->heatmap.empty())
            for (const auto& out : {opt->heatmap, pngPathFor(opt->heatmap)})
                io::refuseToOverwriteInputs(out, {opt->a, opt->b}, "--heatmap");
        io::ExrReader a(opt->a), b(opt->b);
        const std::string layerA = opt->layer.empty() && opt->refLayer.empty() ? commonLayer(a, b)
                                                                                  : opt->layer;
        const std::string layerB = opt->refLayer.empty() ? layerA : opt->refLayer;
        const io::CaptureProfile profileA = io::CaptureProfile::load(opt->profile);
        const io::CaptureProfile profileB =
            opt->refProfile.empty() ? profileA : io::CaptureProfile::load(opt->refProfile);
        const Image imgA = readImage(a, layerA, profileA);
        const Image imgB = readImage(b, layerB, profileB);
        if (imgA.channelCount() != imgB.channelCount())
            throw UsageError(fmt::format("{}[{}] has {} channels but {}[{}] has {}", opt->a,
                                         displayName(layerA), imgA.channelCount(), opt->b,
                                         displayName(layerB), imgB.channelCount()));
        if (imgA.width() != imgB.width() || imgA.height() != imgB.height())
            throw UsageError(fmt::format("{} is {}×{} but {} is {}×{}", opt->a, imgA.width(),
                                         imgA.height(), opt->b, imgB.width(), imgB.height()));
        std::optional<Image> stdErr;
        for (const auto& l : io::listLayers(b))
            if (l.name == layerB + ".StdErr" && int(l.channels.size()) == imgB.channelCount())
                stdErr = io::readLayer(b, l);

        std::optional<Image> mask;
        std::string maskNote = "no mask";
        if (opt->mask == "sky") {
            std::optional<Image> depth = readDepth(opt->b, profileB);
            if (!depth) depth = readDepth(opt->a, profileA);
            if (depth) {
                mask = notSkyMask(*depth, float(opt->skyDistance));
                maskNote = "sky masked by SceneDepth";
            } else {
                maskNote = fmt::format("no SceneDepth in either file (profile {}): nothing masked",
                                       profileB.name());
                logWarning(maskNote);
            }
        }
        Image absError(imgA.width(), imgA.height(), {"Y"});
        ErrorInputs in;
        in.result = &imgA;
        in.reference = &imgB;
        in.referenceStdErr = stdErr ? &*stdErr : nullptr;
        in.mask = mask ? &*mask : nullptr;
        in.tolerance = opt->tolerance;
        const ErrorStats stats = measureError(in, &absError);

        float scale = 0;
        if (!opt->heatmap.empty()) {
            scale = opt->heatMax > 0 ? float(opt->heatMax) : heatScale(absError, in.mask);
            const Image heat = heatmap(absError, in.mask, scale);
            io::ExrMetadata meta;
            meta.strings["framepass:heatScale"] = fmt::format("{}", scale);
            meta.strings["framepass:compare"] = fmt::format("{}[{}] vs {}[{}]", opt->a,
                                                            displayName(layerA), opt->b,
                                                            displayName(layerB));
            io::writeExr(opt->heatmap, {{"heat", {{"Heat", &heat, true}, {"AbsError", &absError, false}}}},
                         meta);
            const DisplayTransform display(io::loadColorConfig(opt->ocioConfig), "scene_linear", "",
                                           "", 0.0f, true);
            // The PNG carries its scale: the colour map from 0 to `scale` under the image.
            io::writePng(pngPathFor(opt->heatmap),
                         io::withColorBar(display.apply(heat), display.apply(heatmapRamp()), "0",
                                          fmt::format("{:.4g}", scale), "|error|"));
        }

        if (opt->json) {
            nlohmann::json j = stats.toJson();
            j["a"] = {{"file", opt->a}, {"layer", layerA}};
            j["b"] = {{"file", opt->b}, {"layer", layerB}};
            j["mask"] = maskNote;
            if (!opt->heatmap.empty())
                j["heatmap"] = {{"exr", opt->heatmap}, {"png", pngPathFor(opt->heatmap)},
                                {"scale", scale}};
            std::cout << j.dump(2) << "\n";
        } else {
            std::cout << fmt::format("{}[{}] against the reference {}[{}]: {} pixels ({}, {} left "
                                     "out)\n",
                                     opt->a, displayName(layerA), opt->b, displayName(layerB),
                                     stats.pixels, maskNote, stats.maskedPixels);
            std::cout << fmt::format("  RMSE            {:.6g}\n  relMSE          {:.6g}\n"
                                     "  SMAPE           {:.6g}\n  MAE             {:.6g}\n"
                                     "  mean bias       {:+.6g}\n  max error       {:.6g}\n"
                                     "  over tolerance  {:.3f} % of pixels (|A−B| > {}·(|B| + "
                                     "0.01))\n",
                                     stats.rmse, stats.relMse, stats.smape, stats.mae, stats.bias,
                                     stats.maxError, 100.0 * stats.overTolerance, stats.tolerance);
            if (stats.noiseRmse)
                std::cout << fmt::format(
                    "  reference noise {:.6g} RMSE ({}): {}\n", *stats.noiseRmse,
                    layerB + ".StdErr",
                    stats.noiseLimited()
                        ? "the error is within twice the reference's own noise: render the "
                          "reference with more samples to measure further"
                        : fmt::format("the error is {:.1f}× the reference's noise",
                                      stats.rmse / std::max(*stats.noiseRmse, 1e-30)));
            else
                std::cout << "  reference noise unknown (no " << layerB << ".StdErr layer)\n";
            if (!opt->heatmap.empty())
                std::cout << fmt::format("heat map: {} and {} (top of the colour map = {:.4g})\n",
                                         opt->heatmap, pngPathFor(opt->heatmap), scale);
        }
        if (opt->maxRmse >= 0 && stats.rmse > opt->maxRmse) {
            std::cerr << fmt::format("framepass: RMSE {:.6g} is above --max-rmse {}\n", stats.rmse,
                                     opt->maxRmse);
            return int(ExitCode::FrameFailed);
        }
        return 0;
    };
}

}  // namespace fp::cli
