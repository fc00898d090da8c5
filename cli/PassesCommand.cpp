// framepass passes: every pass type with its ports and parameters (app/PassCatalogue.h).
#include "app/PassCatalogue.h"
#include "cli/Commands.h"

#include <fmt/ranges.h>

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
                nlohmann::json mine = nlohmann::json::array();
                for (const auto& c : cvars)
                    for (const auto& t : c.value("sets", nlohmann::json::array()))
                        if (t["pass"] == opt->type) {
                            mine.push_back(c);
                            break;
                        }
                cvars = mine;
            }
            if (opt->json) {
                std::cout << cvars.dump(2) << "\n";
                return 0;
            }
            if (opt->markdown) {
                std::cout << app::cvarReferenceMarkdown(cvars);
                return 0;
            }
            for (const auto& c : cvars) {
                std::vector<std::string> sets;
                for (const auto& t : c.value("sets", nlohmann::json::array()))
                    sets.push_back(fmt::format("{}.{} = {}", t["pass"].get<std::string>(),
                                               t["param"].get<std::string>(),
                                               t["default"].dump()));
                std::string what = fmt::format("{}", fmt::join(sets, ", "));
                if (!c["emulated"].get<bool>())
                    what = (c["value"].is_null()
                                ? std::string("not emulated")
                                : fmt::format("not emulated, runs as {}", c["value"].dump())) +
                           ": " + c["note"].get<std::string>();
                std::cout << fmt::format("{:<62} {}\n", c["cvar"].get<std::string>(), what);
            }
            return 0;
        }
        const nlohmann::json all = opt->type.empty()
                                       ? app::passCatalogue()
                                       : nlohmann::json::array({app::describePassType(opt->type)});
        if (opt->json) {
            std::cout << (opt->type.empty() ? all : all[0]).dump(2) << "\n";
            return 0;
        }
        if (opt->markdown) {
            std::cout << app::passReferenceMarkdown(all);
            return 0;
        }
        for (const auto& t : all) {
            std::cout << fmt::format("{:<22} {}\n", t["type"].get<std::string>(),
                                     t["doc"].get<std::string>());
            if (opt->type.empty())
                continue;
            for (const char* dir : {"inputs", "outputs"}) {
                std::cout << "  " << dir << ":\n";
                for (const auto& p : t[dir]) {
                    const auto ch = p["channels"].get<std::vector<std::string>>();
                    std::cout << fmt::format(
                        "    {:<14} {:<8} {:<6}{}{} — {}\n", p["name"].get<std::string>(),
                        ch.empty() ? "any" : fmt::format("{}", fmt::join(ch, "")),
                        p["kind"].get<std::string>(), p["optional"].get<bool>() ? " optional" : "",
                        p["default"].get<std::string>().empty()
                            ? ""
                            : " ← " + p["default"].get<std::string>(),
                        p["doc"].get<std::string>());
                }
            }
            std::cout << "  params:\n";
            for (const auto& p : t["params"]) {
                std::string range;
                if (p.contains("min"))
                    range = fmt::format(" [{}, {}]", p["min"].dump(), p["max"].dump());
                std::cout << fmt::format("    {:<22} {:<6} = {:<10}{} — {}\n",
                                         p["name"].get<std::string>(), p["type"].get<std::string>(),
                                         p["default"].dump(), range, p["doc"].get<std::string>());
            }
            for (const auto& c : t["cvars"])
                std::cout << fmt::format("  cvar {} → {}\n", c["cvar"].get<std::string>(),
                                         c["param"].get<std::string>());
        }
        return 0;
    };
}

}  // namespace fp::cli
