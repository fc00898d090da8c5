#include "app/PassCatalogue.h"

#include "app/Settings.h"
#include "framework/CvarTable.h"
#include "foundation/Error.h"
#include "foundation/Suggest.h"

#include <fmt/ranges.h>

#include <algorithm>

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
    const CvarTable& table = builtinCvarTable();
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
                                      : fmt::format("`{}`", p["default"].get<std::string>()),
                                  cell(p["doc"].get<std::string>()));
            }
        }
        if (!t["params"].empty()) {
            md += "\n| parameter | type | default | range | cvars | |\n|---|---|---|---|---|---|\n";
            for (const auto& p : t["params"]) {
                std::vector<std::string> cvars;
                for (const auto& c : t["cvars"])
                    if (c["param"] == p["name"]) cvars.push_back(fmt::format("`{}`", c["cvar"].get<std::string>()));
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

namespace {
// A parameter's value as a cvar is written: booleans as Unreal's 0/1, floats at float precision.
std::string cvarValue(const nlohmann::json& v, const std::string& type) {
    if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
    if (type == "float" && v.is_number()) return fmt::format("{}", v.get<float>());
    if (v.is_number()) return fmt::format("{}", v.get<double>());
    if (v.is_string()) return v.get<std::string>();
    return v.dump();
}

// What a parameter accepts, as a cvar: its range, its choices, or 0/1.
std::string cvarValues(const nlohmann::json& target) {
    const std::string type = target["type"].get<std::string>();
    if (type == "bool") return "0, 1";
    if (target.contains("min"))
        return fmt::format("{} … {}", cvarValue(target["min"], type),
                           cvarValue(target["max"], type));
    if (target.contains("choices")) {
        std::vector<std::string> c;
        for (const auto& v : target["choices"]) c.push_back(fmt::format("`{}`", v.get<std::string>()));
        return fmt::format("{}", fmt::join(c, ", "));
    }
    return "any " + type;
}

// One cell for every target: the text once when they agree, else each with its pass.
template <class F>
std::string perTarget(const nlohmann::json& sets, F text) {
    std::vector<std::string> each;
    for (const auto& t : sets) each.push_back(text(t));
    if (std::all_of(each.begin(), each.end(), [&](const std::string& e) { return e == each[0]; }))
        return each.empty() ? "" : each[0];
    std::vector<std::string> out;
    for (std::size_t i = 0; i < each.size(); ++i)
        out.push_back(fmt::format("{} ({})", each[i], sets[i]["pass"].get<std::string>()));
    return fmt::format("{}", fmt::join(out, "; "));
}
}  // namespace

nlohmann::json cvarCatalogue() {
    const PassRegistry& reg = builtinPasses();
    const CvarTable table(reg);
    std::vector<std::string> names = table.names();
    std::stable_sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
        return asciiLowercase(a) < asciiLowercase(b);
    });
    nlohmann::json all = nlohmann::json::array();
    for (const auto& name : names) {
        nlohmann::json sets = nlohmann::json::array();
        nlohmann::json entry = {{"cvar", name}};
        for (const auto& m : table.all()) {
            if (m.cvar != name) continue;
            if (m.passType.empty()) {
                entry["value"] = m.emulatedValue;
                entry["note"] = m.note;
                continue;
            }
            const PassType* type = reg.find(m.passType);
            const auto p = std::find_if(type->params.begin(), type->params.end(),
                                        [&](const ParamInfo& i) { return i.name == m.param; });
            nlohmann::json t = {{"pass", m.passType},   {"param", m.param},
                                {"type", p->type},      {"default", p->defaultValue},
                                {"doc", p->doc}};
            if (p->min) t["min"] = *p->min;
            if (p->max) t["max"] = *p->max;
            if (!p->choices.empty()) t["choices"] = p->choices;
            sets.push_back(t);
        }
        entry["emulated"] = !sets.empty();
        if (!sets.empty()) entry["sets"] = sets;
        all.push_back(entry);
    }
    return all;
}

// docs/config.md's cvar table (tests/docs/check_docs.py checks the committed section matches).
std::string cvarReferenceMarkdown(const nlohmann::json& cvars) {
    std::string md =
        "| cvar | sets | values | default | emulated | meaning |\n"
        "|---|---|---|---|---|---|\n";
    for (const auto& c : cvars) {
        const std::string name = fmt::format("`{}`", c["cvar"].get<std::string>());
        if (!c["emulated"].get<bool>()) {
            const nlohmann::json& v = c["value"];
            md += fmt::format("| {} | | {} | | no | {} |\n", name,
                              v.is_null() ? "any value warns"
                                          : fmt::format("`{}` (another value warns)",
                                                        cvarValue(v, "")),
                              cell(c["note"].get<std::string>()));
            continue;
        }
        const nlohmann::json& sets = c["sets"];
        std::vector<std::string> targets;
        for (const auto& t : sets)
            targets.push_back(fmt::format("`{}.{}`", t["pass"].get<std::string>(),
                                          t["param"].get<std::string>()));
        md += fmt::format(
            "| {} | {} | {} | {} | yes | {} |\n", name, fmt::join(targets, ", "),
            perTarget(sets, [](const nlohmann::json& t) { return cvarValues(t); }),
            perTarget(sets,
                      [](const nlohmann::json& t) {
                          return fmt::format("`{}`", cvarValue(t["default"], t["type"].get<std::string>()));
                      }),
            cell(sets[0]["doc"].get<std::string>()));
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

nlohmann::json cvarsOfPass(const nlohmann::json& cvars, const std::string& type) {
    nlohmann::json mine = nlohmann::json::array();
    for (const auto& c : cvars)
        for (const auto& t : c.value("sets", nlohmann::json::array()))
            if (t["pass"] == type) {
                mine.push_back(c);
                break;
            }
    return mine;
}

std::string passReferenceText(const nlohmann::json& all, bool detailed) {
    std::string out;
    for (const auto& t : all) {
        out += fmt::format("{:<22} {}\n", t["type"].get<std::string>(),
                                 t["doc"].get<std::string>());
        if (!detailed)
            continue;
        for (const char* dir : {"inputs", "outputs"}) {
            out += fmt::format("  {}:\n", dir);
            for (const auto& p : t[dir]) {
                const auto ch = p["channels"].get<std::vector<std::string>>();
                out += fmt::format(
                    "    {:<14} {:<8} {:<6}{}{} — {}\n", p["name"].get<std::string>(),
                    ch.empty() ? "any" : fmt::format("{}", fmt::join(ch, "")),
                    p["kind"].get<std::string>(), p["optional"].get<bool>() ? " optional" : "",
                    p["default"].get<std::string>().empty()
                        ? ""
                        : " ← " + p["default"].get<std::string>(),
                    p["doc"].get<std::string>());
            }
        }
        out += "  params:\n";
        for (const auto& p : t["params"]) {
            std::string range;
            if (p.contains("min"))
                range = fmt::format(" [{}, {}]", p["min"].dump(), p["max"].dump());
            out += fmt::format("    {:<22} {:<6} = {:<10}{} — {}\n",
                                     p["name"].get<std::string>(), p["type"].get<std::string>(),
                                     p["default"].dump(), range, p["doc"].get<std::string>());
        }
        for (const auto& c : t["cvars"])
            out += fmt::format("  cvar {} → {}\n", c["cvar"].get<std::string>(),
                                     c["param"].get<std::string>());
    }
    return out;
}

std::string cvarReferenceText(const nlohmann::json& cvars) {
    std::string out;
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
        out += fmt::format("{:<62} {}\n", c["cvar"].get<std::string>(), what);
    }
    return out;
}

}  // namespace fp::app
