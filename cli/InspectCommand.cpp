// framepass inspect: what a capture holds — channels, their buffers, camera, statistics
// (app/Inspect.h does the work).
#include "app/Inspect.h"
#include "cli/Commands.h"
#include "io/CaptureProfile.h"

#include <fmt/ranges.h>

#include <iostream>

namespace fp::cli {

Command addInspectCommand(CLI::App& app) {
    struct Options {
        std::string capture, profile = "canonical", camera;
        bool json = false;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand("inspect", "list a capture's channels, the buffers its "
                                                  "profile reads from them, its camera and "
                                                  "per-channel statistics");
    sub->add_option("capture", opt->capture,
                    "capture EXR (multi-file profiles: the base or any one of its files)")
        ->required();
    sub->add_option("--profile", opt->profile,
                    "capture profile, NAME or FILE.json (default canonical): " +
                        fmt::format("{}", fmt::join(io::CaptureProfile::builtinNames(), ", ")));
    sub->add_option("--camera", opt->camera,
                    "camera sidecar to use, as a config's \"camera\" (default: "
                    "<capture>.camera.json beside the capture, else the header)");
    sub->add_flag("--json", opt->json, "machine-readable output");

    return [opt]() {
        const nlohmann::json j = app::inspectCapture(opt->capture, opt->profile, opt->camera);
        if (opt->json) std::cout << j.dump(2) << "\n";
        else std::cout << app::inspectionText(j);
        return 0;
    };
}

}  // namespace fp::cli
