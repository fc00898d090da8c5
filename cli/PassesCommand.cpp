// framepass passes: every pass type with its ports and parameters (app/PassCatalogue.h).
#include "app/PassCatalogue.h"
#include "cli/Commands.h"

#include <iostream>

namespace fp::cli {

Command addPassesCommand(CLI::App& app) {
    struct Options {
        std::string type;
        bool json = false, markdown = false, cvars = false;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub =
        app.add_subcommand("passes", "list pass types, or the ports and parameters of one");
    sub->add_option("type", opt->type, "a pass type id");
    auto* json = sub->add_flag("--json", opt->json, "machine-readable output");
    sub->add_flag("--markdown", opt->markdown,
                  "the pass reference as Markdown (docs/passes.md is this output; with --cvars, "
                  "docs/config.md's cvar table)")
        ->excludes(json);
    sub->add_flag("--cvars", opt->cvars,
                  "every cvar framepass knows (of TYPE's parameters, with TYPE): what it sets, "
                  "its values and default");

    return [opt]() {
        if (opt->cvars) {
            nlohmann::json cvars = app::cvarCatalogue();
            if (!opt->type.empty()) {
                app::describePassType(opt->type);  // an unknown type is an error, with a suggestion
                cvars = app::cvarsOfPass(cvars, opt->type);
            }
            std::cout << (opt->json       ? cvars.dump(2) + "\n"
                          : opt->markdown ? app::cvarReferenceMarkdown(cvars)
                                          : app::cvarReferenceText(cvars));
            return 0;
        }
        const nlohmann::json all = opt->type.empty()
                                       ? app::passCatalogue()
                                       : nlohmann::json::array({app::describePassType(opt->type)});
        std::cout << (opt->json       ? (opt->type.empty() ? all : all[0]).dump(2) + "\n"
                      : opt->markdown ? app::passReferenceMarkdown(all)
                                      : app::passReferenceText(all, !opt->type.empty()));
        return 0;
    };
}

}  // namespace fp::cli
