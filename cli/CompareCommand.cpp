// framepass compare: error of one image against a reference (app/Compare.h does the work).
#include "app/Compare.h"
#include "cli/Commands.h"
#include "cli/Flags.h"
#include "foundation/Error.h"

#include <algorithm>
#include <iostream>

namespace fp::cli {

namespace {
std::string displayName(const std::string& layer) { return layer.empty() ? "\"\"" : layer; }
}  // namespace

Command addCompareCommand(CLI::App& app) {
    auto opt = std::make_shared<app::CompareOptions>();
    CLI::App* sub = app.add_subcommand(
        "compare", "error of image A against reference B: RMSE, relMSE, SMAPE, MAE, bias, max, "
                   "fraction over tolerance, the reference's own noise, and a heat map");
    sub->add_option("a", opt->a, "result: an EXR, or a PNG/JPEG/TIFF read through OpenImageIO")
        ->required();
    sub->add_option("b", opt->b, "reference (e.g. a capture with Truth.* layers)")->required();
    sub->add_option("--layer", opt->layer,
                    "what to compare (in A, and in B unless --ref-layer): a layer (Truth.AO), one "
                    "channel of it (ViewLayer.AO.R) or a product (ViewLayer.GlossInd*ViewLayer."
                    "GlossCol)");
    sub->add_option("--ref-layer", opt->refLayer, "the same for B, when it is named differently");
    sub->add_option("--mask", opt->masks,
                    "which pixels count (repeatable, masks multiply): sky (default: leave out "
                    "the sky, where the profile finds SceneDepth), none, shading-model=N, id=N "
                    "(InstanceId), reflected-emitter[=F] (leave out the pixels whose reflection "
                    "sees an emitter, from a truth capture's Truth.ReflectedEmitter; with the sky: "
                    "--mask sky --mask reflected-emitter), or a picture whose first channel > 0 "
                    "marks the kept pixels");
    sub->add_option("--profile", opt->profile,
                    "capture profile (NAME or FILE.json, default canonical): a --layer that names "
                    "a buffer it maps (SceneDepth, WorldNormal, …) is read through it, and it "
                    "finds SceneDepth for the sky mask");
    sub->add_option("--max-memory", opt->maxMemory,
                    "refuse to read when the forecast peak (both images, the masks, the error "
                    "and heat map planes, this process) is above this (8G, 512M, bytes; default "
                    "as run's)");
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
                    "write |A−B| as an EXR heat map here, plus a .png preview next to it")
        ->check(nonEmptyPath());
    sub->add_option("--heat-max", opt->heatMax,
                    "error at the top of the colour map (default: the 99th percentile)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--max-rmse", opt->maxRmse, "exit with 1 when the RMSE is above this")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--ocio-config", opt->ocioConfig,
                    "OCIO config for the PNG preview (default $OCIO, then framepass's own)");
    sub->add_option("--flip", opt->flip,
                    "FLIP, NVIDIA's perceptual error, beside the figures: auto (LDR-FLIP when A "
                    "is a picture, else HDR-FLIP), hdr, ldr or off")
        ->check(CLI::IsMember({"auto", "hdr", "ldr", "off"}));
    sub->add_option("--ppd", opt->pixelsPerDegree,
                    "FLIP's observer in pixels per degree of visual angle (default 67.02: a 0.7 m "
                    "wide 3840-pixel monitor seen from 0.7 m)")
        ->check(CLI::PositiveNumber);

    return [opt]() {
        const app::CompareResult r = app::compareFiles(*opt);
        const ErrorStats& stats = r.stats;
        const std::string &layerA = r.layerA, &layerB = r.layerB, &maskNote = r.maskNote;
        const float scale = r.heatScale;
        if (opt->json) {
            std::cout << r.toJson(*opt).dump(2) << "\n";
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
            if (stats.nonFinitePixels > 0)
                std::cout << fmt::format("  non-finite      {} pixels (NaN or inf in A or B)\n",
                                         stats.nonFinitePixels);
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
            if (const auto& f = r.flip)
                std::cout << fmt::format(
                    "  FLIP            {:.6g} ({}, {:.4g} pixels per degree{})\n", f->mean,
                    f->hdr ? "HDR-FLIP" : "LDR-FLIP", opt->pixelsPerDegree,
                    f->hdr ? fmt::format(", {} exposures from {:+.3g} to {:+.3g} stops",
                                         f->exposures, f->startExposure, f->stopExposure)
                           : "");
            if (!opt->heatmap.empty())
                std::cout << fmt::format("heat map: {} and {} (top of the colour map = {:.4g})\n",
                                         opt->heatmap, app::heatmapPngPath(opt->heatmap), scale);
        }
        if (stats.nonFinitePixels > 0)
            std::cerr << fmt::format("framepass: warning: {} pixels hold a NaN or an infinity in "
                                     "A or B; they count as over tolerance, max error is inf, and "
                                     "the other figures are over the {} finite pixels\n",
                                     stats.nonFinitePixels, stats.pixels - stats.nonFinitePixels);
        if (opt->maxRmse >= 0 && stats.nonFinitePixels > 0) {
            std::cerr << fmt::format("framepass: {} non-finite pixels fail --max-rmse {}\n",
                                     stats.nonFinitePixels, opt->maxRmse);
            return int(ExitCode::FrameFailed);
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
