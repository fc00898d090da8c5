#include "app/PassCatalogue.h"

#include "framework/CvarTable.h"
#include "foundation/Error.h"
#include "foundation/Suggest.h"

#include <fmt/ranges.h>

namespace fp::app {

namespace {
// Markdown cells hold no raw '|' or newline.
std::string cell(const std::string& text) {
    std::string out;
    for (char c : text) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
    return out;
}
}  // namespace

nlohmann::json describePassType(const PassType& t) {
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
            {"needsCamera", io.needsCamera},
            {"cuda", pass->hasCudaKernel()}};
}

// docs/passes.md: every pass type's ports, parameters and cvars, made from the same specs that
// validate configs (tests/cli/cli_test.sh checks the committed file matches).
std::string passReferenceMarkdown(const nlohmann::json& all) {
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


nlohmann::json passCatalogue() {
    nlohmann::json all = nlohmann::json::array();
    for (const auto& t : builtinPasses().types())
        all.push_back(describePassType(t));
    return all;
}

nlohmann::json describePassType(const std::string& id) {
    const PassRegistry& reg = builtinPasses();
    const PassType* t = reg.find(id);
    if (!t)
        throw UsageError(fmt::format("unknown pass type '{}'{}", id, didYouMean(id, reg.ids())));
    return describePassType(*t);
}

}  // namespace fp::app
