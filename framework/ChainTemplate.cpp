#include "framework/ChainTemplate.h"

#include "foundation/Scene.h"

#include <fmt/format.h>

#include <regex>

namespace fp {

namespace {

const std::vector<std::string> kPlaceholders = {"{light}", "{lightName}", "{colorIn}",
                                                "{colorOut}"};

struct Substitution {
    std::string light, lightName, colorIn, colorOut;

    std::string operator()(std::string text) const {
        const std::string values[] = {light, lightName, colorIn, colorOut};
        for (std::size_t k = 0; k < kPlaceholders.size(); ++k)
            for (auto at = text.find(kPlaceholders[k]); at != std::string::npos;
                 at = text.find(kPlaceholders[k], at + values[k].size()))
                text.replace(at, kPlaceholders[k].size(), values[k]);
        return text;
    }
    nlohmann::json operator()(const nlohmann::json& j) const {
        if (j.is_string())
            return (*this)(j.get<std::string>());
        nlohmann::json out = j;
        if (j.is_object() || j.is_array())
            for (auto& v : out)
                v = (*this)(nlohmann::json(v));
        return out;
    }
};

// Every "{word}" of a template string must be a known placeholder.
void checkPlaceholders(const std::string& text, const std::string& pointer, Diagnostics& diag) {
    static const std::regex kWord(R"(\{[A-Za-z]+\})");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), kWord);
         it != std::sregex_iterator(); ++it)
        if (std::find(kPlaceholders.begin(), kPlaceholders.end(), it->str()) == kPlaceholders.end())
            diag.error(pointer, fmt::format("unknown placeholder '{}' (known: {})", it->str(),
                                            fmt::join(kPlaceholders, ", ")));
}

void checkTemplate(const LightTemplate& t, Diagnostics& diag) {
    for (std::size_t k = 0; k < t.passes.size(); ++k) {
        const std::string at = t.pointer + "/passes/" + std::to_string(k);
        checkPlaceholders(t.passes[k].name, at + "/name", diag);
        checkPlaceholders(t.passes[k].params.dump(), at + "/params", diag);
        for (const auto& [port, source] : t.passes[k].inputs)
            checkPlaceholders(source, at + "/inputs/" + jsonPointerEscape(port), diag);
    }
    checkPlaceholders(t.colorIn + t.colorOut, t.pointer, diag);
    for (const auto& [target, source] : t.rewire)
        checkPlaceholders(source, t.pointer + "/rewire/" + jsonPointerEscape(target), diag);
}

// One copy of the template's passes per light, each adding into the previous light's colour.
std::vector<NodeDesc> expandPasses(const LightTemplate& t,
                                   const std::vector<std::string>& ids,
                                   const std::vector<std::string>& names,
                                   std::string& colorOut) {
    std::vector<NodeDesc> nodes;
    std::string colorIn = t.colorIn;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        const Substitution sub{ids[i], names[i], colorIn, ""};
        for (std::size_t k = 0; k < t.passes.size(); ++k) {
            const NodeDesc& p = t.passes[k];
            NodeDesc n{sub(p.name),
                       p.type,
                       sub(p.params),
                       {},
                       fmt::format("{}/passes/{} (light '{}')", t.pointer, k, names[i])};
            for (const auto& [port, source] : p.inputs)
                n.inputs[port] = sub(source);
            nodes.push_back(std::move(n));
        }
        colorIn = sub(t.colorOut);
    }
    colorOut = colorIn;
    return nodes;
}

// The files a template writes: a source with a per-light placeholder repeats for every light
// (light by light, in the order written); any other source is written once.
std::vector<OutputDesc> expandOutputs(const LightTemplate& t,
                                      const std::vector<std::string>& ids,
                                      const std::vector<std::string>& names,
                                      const std::string& colorOut) {
    std::vector<OutputDesc> outputs;
    for (const OutputDesc& o : t.outputs) {
        OutputDesc e{o.file, {}, o.pointer, o.isDump};
        for (std::size_t i = 0; i < ids.size(); ++i) {
            const Substitution sub{ids[i], names[i], "", colorOut};
            for (const auto& source : o.sources) {
                const bool perLight = source.find("{light") != std::string::npos;
                if (perLight || i == 0)
                    e.sources.push_back(sub(source));
            }
        }
        outputs.push_back(std::move(e));
    }
    return outputs;
}

// rewire: "pass.inputPort" → source, applied to the expanded chain.
void applyRewire(const LightTemplate& t,
                 const std::string& colorOut,
                 GraphDesc& g,
                 Diagnostics& diag) {
    const Substitution sub{"", "", "", colorOut};
    for (const auto& [target, source] : t.rewire) {
        const std::string at = t.pointer + "/rewire/" + jsonPointerEscape(target);
        const auto dot = target.find('.');
        if (dot == std::string::npos) {
            diag.error(at, fmt::format("'{}' should be 'pass.inputPort'", target));
            continue;
        }
        const std::string pass = target.substr(0, dot);
        auto node = std::find_if(g.nodes.begin(), g.nodes.end(),
                                 [&](const NodeDesc& n) { return n.name == pass; });
        if (node == g.nodes.end()) {
            diag.error(at, fmt::format("the chain has no pass named '{}'", pass));
            continue;
        }
        node->inputs[target.substr(dot + 1)] = sub(source);
    }
}

}  // namespace

GraphDesc expandLightTemplates(const GraphDesc& graph,
                               const std::vector<std::string>& lightNames,
                               Diagnostics& diag,
                               std::vector<ExpandedTemplate>* expanded) {
    GraphDesc g = graph;
    g.lightTemplates.clear();
    const std::vector<std::string> ids = lightIdentifiers(lightNames);
    // Later templates first, so the positions of earlier ones still hold; their files are added
    // in the order the templates are written.
    std::vector<std::vector<OutputDesc>> outputs;
    for (auto t = graph.lightTemplates.rbegin(); t != graph.lightTemplates.rend(); ++t) {
        checkTemplate(*t, diag);
        if (ids.empty())
            continue;
        std::string colorOut;
        std::vector<NodeDesc> nodes = expandPasses(*t, ids, lightNames, colorOut);
        if (expanded) {
            ExpandedTemplate e{t->pointer, ids, {}};
            for (const auto& n : nodes)
                e.passes.push_back(n.name);
            expanded->insert(expanded->begin(), std::move(e));
        }
        const std::size_t at = std::min(t->position, g.nodes.size());
        g.nodes.insert(g.nodes.begin() + std::ptrdiff_t(at), nodes.begin(), nodes.end());
        applyRewire(*t, colorOut, g, diag);
        outputs.insert(outputs.begin(), expandOutputs(*t, ids, lightNames, colorOut));
    }
    for (const auto& files : outputs)
        g.outputs.insert(g.outputs.end(), files.begin(), files.end());
    return g;
}

}  // namespace fp
