// framepass sheet: a capture's buffers (or a folder's EXR layers) as one labelled PNG contact
// sheet (app/Sheet.h does the work).
#include "app/Sheet.h"
#include "cli/Commands.h"
#include "cli/Flags.h"

#include <iostream>

namespace fp::cli {

Command addSheetCommand(CLI::App& app) {
    struct Options : SheetOptions {
        bool json = false;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand(
        "sheet",
        "every buffer of a capture (or every layer of every EXR in a folder, e.g. a "
        "run's dumps) as a labelled tile of one PNG contact sheet");
    sub->add_option("input", opt->input, "capture EXR, or a folder of EXRs")->required();
    sub->add_option("-o,--output", opt->output, "the PNG to write")->required()->check(nonEmptyPath());
    sub->add_option("--profile", opt->profile,
                    "capture profile (NAME or FILE.json, default canonical) through which a "
                    "capture's buffers are read");
    sub->add_option("--columns", opt->columns, "tiles per row (default: ⌈√tiles⌉)")
        ->check(CLI::Range(1, 1000));
    sub->add_option("--tile", opt->tile,
                    "tile width in pixels (default: the image width, at most 256)")
        ->check(CLI::Range(8, 8192));
    sub->add_option("--ocio-config", opt->ocioConfig,
                    "OCIO config for colour tiles (default $OCIO, then framepass's own)");
    sub->add_flag("--json", opt->json, "print the tiles (name, kind, range) as JSON");

    return [opt]() {
        const nlohmann::json j = writeSheet(*opt);
        if (opt->json) {
            std::cout << j.dump(2) << "\n";
            return 0;
        }
        std::cout << fmt::format("wrote {} ({}×{}: {} tiles, {} columns × {} rows)\n",
                                 opt->output, j["width"].get<int>(), j["height"].get<int>(),
                                 j["tiles"].size(), j["columns"].get<int>(), j["rows"].get<int>());
        for (const auto& t : j["tiles"])
            std::cout << fmt::format("  {:<7} {}\n", t["kind"].get<std::string>(),
                                     t["label"].get<std::string>());
        return 0;
    };
}

}  // namespace fp::cli
