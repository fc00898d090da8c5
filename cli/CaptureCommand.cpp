// framepass capture: render a canonical capture of a scene (app/Capture.h does the work).
#include "app/Capture.h"
#include "cli/Commands.h"
#include "cli/Flags.h"

#include <iostream>

namespace fp::cli {

Command addCaptureCommand(CLI::App& app) {
    auto opt = std::make_shared<app::CaptureOptions>();
    CLI::App* sub = app.add_subcommand(
        "capture", "render a canonical capture (every GBuffer buffer, SceneColor, previous frame, "
                   "velocity) from a scene JSON");
    sub->add_option("scene", opt->scene, "scene JSON naming a .gltf/.glb/.obj")->required();
    sub->add_option("-o,--output", opt->output, "output EXR (#### / %04d for sequences)")
        ->required()
        ->check(nonEmptyPath());
    sub->add_option("--width", opt->width, "width in pixels (default: the scene's resolution)")
        ->check(CLI::Range(1, 16384));
    sub->add_option("--height", opt->height, "height in pixels")->check(CLI::Range(1, 16384));
    auto* frameOpt = sub->add_option("--frame", opt->frame, "frame number (moves the camera by "
                                                             "cameraMotion; seeds sampling)");
    sub->add_option("--frames", opt->frames, "frame spec for a sequence, e.g. 1-6")
        ->excludes(frameOpt);
    sub->add_option("--light-samples", opt->lightSamples,
                    "shadow samples per pixel for lights with size")
        ->check(CLI::Range(1, 4096));
    auto* halfOpt = sub->add_flag("--half", opt->half,
                                  "store every GBuffer buffer as half float, as Movie Render "
                                  "Queue's 16-bit EXR does (truth layers stay float32)");
    sub->add_flag("--float-depth", opt->floatDepth,
                  "with --half: SceneDepth and PrevSceneDepth stay float32")
        ->needs(halfOpt);
    sub->add_flag("--truth", opt->truth, "add Truth.* layers (and their .StdErr) from the "
                                          "reference path tracer");
    sub->add_option("--truth-spp", opt->truthSpp, "reference samples per pixel (default 256)")
        ->check(CLI::Range(1, 1 << 20));
    sub->add_option("--truth-ao-radius", opt->aoRadiusMeters,
                    "Truth.AO radius in metres (default 1)")
        ->check(CLI::PositiveNumber);

    return [opt]() {
        app::captureScene(*opt, std::cout);
        return 0;
    };
}

}  // namespace fp::cli
