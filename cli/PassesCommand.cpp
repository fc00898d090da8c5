// framepass passes: every pass type with its ports and parameters, from the spec that validates.
#include "cli/Commands.h"
#include "passes/core/CvarTable.h"
#include "passes/core/Error.h"
#include "passes/core/PassRegistry.h"
#include "passes/core/Suggest.h"

#include <fmt/ranges.h>

#include <iostream>

namespace fp::cli {

namespace {
nlohmann::json describeType(const PassType& t) {
    Diagnostics diag;
    nlohmann::json resolved;
    const auto pass = t.create(nlohmann::json::object(), "", diag, resolved);
    const PassIO io = pass->describe();
    auto ports = [](const std::vector<PortSpec>& list) {
        nlohmann::json a = nlohmann::json::array();
        for (const auto& p : list)
            a.push_back({{"name", p.name},
                         {"channels", p.channels},
                         {"kind", p.kind == PortKind::Color ? "color" : "data"},
                         {"optional", p.optional},
                         {"default", p.captureDefault.empty() ? "" : "capture:" + p.captureDefault},
                         {"doc", p.doc}});
        return a;
    };
    nlohmann::json params = nlohmann::json::array();
    for (const auto& p : t.params) {
        nlohmann::json pj = {
            {"name", p.name}, {"type", p.type}, {"default", p.defaultValue}, {"doc", p.doc}};
        if (p.min)
            pj["min"] = *p.min;
        if (p.max)
            pj["max"] = *p.max;
        if (!p.choices.empty())
            pj["choices"] = p.choices;
        params.push_back(pj);
    }
    nlohmann::json cvars = nlohmann::json::array();
    const CvarTable table(builtinPasses());  // named: a range-for over a temporary's member dangles
    for (const auto& c : table.all())
        if (c.passType == t.id)
            cvars.push_back({{"cvar", c.cvar}, {"param", c.param}, {"note", c.note}});
    return {{"type", t.id},
            {"doc", t.doc},
            {"inputs", ports(io.inputs)},
            {"outputs", ports(io.outputs)},
            {"params", params},
            {"cvars", cvars},
            {"needsScene", io.needsScene},
            {"needsCamera", io.needsCamera}};
}
// Markdown cells hold no raw '|' or newline.
std::string cell(const std::string& text) {
    std::string out;
    for (char c : text) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
    return out;
}

// docs/passes.md: every pass type's ports, parameters and cvars, made from the same specs that
// validate configs (tests/cli/cli_test.sh checks the committed file matches).
std::string markdown(const nlohmann::json& all) {
    std::string md =
        "# Pass reference\n\n"
        "Written by `framepass passes --markdown` from each pass's declarations (its ports and "
        "`ParamSpec`), the same specs that validate configs; `make test` checks this file "
        "matches the code. What the passes compute, and why, is in "
        "[algorithms.md](algorithms.md).\n\n";
    for (const auto& t : all) md += fmt::format("- [`{0}`](#{0})\n", t["type"].get<std::string>());
    for (const auto& t : all) {
        md += fmt::format("\n## {}\n\n{}\n", t["type"].get<std::string>(),
                          t["doc"].get<std::string>());
        if (t["needsScene"].get<bool>()) md += "\nTraces rays: loads the scene's geometry.\n";
        for (const char* dir : {"inputs", "outputs"}) {
            if (t[dir].empty()) continue;
            md += fmt::format("\n| {} | channels | kind | default | |\n|---|---|---|---|---|\n",
                              std::string(dir) == "inputs" ? "input" : "output");
            for (const auto& p : t[dir]) {
                const auto ch = p["channels"].get<std::vector<std::string>>();
                md += fmt::format("| `{}` | {} | {}{} | {} | {} |\n", p["name"].get<std::string>(),
                                  ch.empty() ? "any" : fmt::format("{}", fmt::join(ch, " ")),
                                  p["kind"].get<std::string>(),
                                  p["optional"].get<bool>() ? ", optional" : "",
                                  p["default"].get<std::string>().empty()
                                      ? ""
                                      : "`" + p["default"].get<std::string>() + "`",
                                  cell(p["doc"].get<std::string>()));
            }
        }
        if (!t["params"].empty()) {
            md += "\n| parameter | type | default | range | cvars | |\n|---|---|---|---|---|---|\n";
            for (const auto& p : t["params"]) {
                std::vector<std::string> cvars;
                for (const auto& c : t["cvars"])
                    if (c["param"] == p["name"]) cvars.push_back("`" + c["cvar"].get<std::string>() + "`");
                md += fmt::format(
                    "| `{}` | {} | `{}` | {} | {} | {} |\n", p["name"].get<std::string>(),
                    p["type"].get<std::string>(), p["default"].dump(),
                    p.contains("min") ? fmt::format("{} … {}", p["min"].dump(), p["max"].dump())
                                      : "",
                    fmt::join(cvars, ", "), cell(p["doc"].get<std::string>()));
            }
        }
    }
    return md;
}

}  // namespace

Command addPassesCommand(CLI::App& app) {
    struct Options {
        std::string type;
        bool json = false, markdown = false;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub =
        app.add_subcommand("passes", "list pass types, or the ports and parameters of one");
    sub->add_option("type", opt->type, "a pass type id");
    auto* json = sub->add_flag("--json", opt->json, "machine-readable output");
    sub->add_flag("--markdown", opt->markdown,
                  "the pass reference as Markdown (docs/passes.md is this output)")
        ->excludes(json);

    return [opt]() {
        const PassRegistry& reg = builtinPasses();
        nlohmann::json all = nlohmann::json::array();
        for (const auto& t : reg.types())
            if (opt->type.empty() || t.id == opt->type)
                all.push_back(describeType(t));
        if (!opt->type.empty() && all.empty())
            throw UsageError(fmt::format("unknown pass type '{}'{}", opt->type,
                                         didYouMean(opt->type, reg.ids())));
        if (opt->json) {
            std::cout << (opt->type.empty() ? all : all[0]).dump(2) << "\n";
            return 0;
        }
        if (opt->markdown) {
            std::cout << markdown(all);
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
