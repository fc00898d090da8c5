#include "io/LightChain.h"

#include "passes/core/Error.h"

#include <algorithm>
#include <cctype>
#include <set>

namespace fp::io {

namespace {
constexpr const char* kComposite = "diffuse_indirect_composite";
constexpr const char* kDisplay = "display";

NodeDesc* findNode(GraphDesc& g, const std::string& name) {
    for (auto& n : g.nodes)
        if (n.name == name) return &n;
    return nullptr;
}
}  // namespace

std::string passSuffix(const std::string& lightName) {
    std::string s;
    for (unsigned char c : lightName) s += std::isalnum(c) ? char(std::tolower(c)) : '_';
    return s.empty() ? "light" : s;
}

void addLightPasses(GraphDesc& graph, const std::vector<std::string>& lightNames, bool addOutputs) {
    NodeDesc* composite = findNode(graph, kComposite);
    FP_ASSERT(composite && findNode(graph, kDisplay));  // every preset chain has both
    if (lightNames.empty()) return;
    composite->inputs["sceneColor"] = "capture:Emissive";
    const std::string pointer = composite->pointer;

    std::vector<NodeDesc> added;
    std::set<std::string> used;
    std::string color = std::string(kComposite) + ".color";
    std::vector<std::string> shadowLayers;
    for (const std::string& light : lightNames) {
        std::string id = passSuffix(light);
        for (int k = 2; used.count(id); ++k) id = passSuffix(light) + "_" + std::to_string(k);
        used.insert(id);
        const nlohmann::json params = {{"light", light}};
        const std::string shadows = "rt_shadows_" + id, denoise = "shadow_denoise_" + id,
                          lighting = "deferred_lighting_" + id;
        added.push_back({shadows, "rt_shadows", params, {}, pointer});
        added.push_back({denoise, "shadow_denoise", params,
                         {{"shadow", shadows + ".shadow"},
                          {"transmission", shadows + ".transmission"},
                          {"hitDistance", shadows + ".hitDistance"}},
                         pointer});
        added.push_back({lighting, "deferred_lighting", params,
                         {{"color", color}, {"attenuation", denoise + ".lightAttenuation"}},
                         pointer});
        color = lighting + ".color";
        shadowLayers.push_back(denoise + ".shadow");
        shadowLayers.push_back(shadows + ".shadow");
    }
    // The lights run after the composite and before the display (reference §10).
    const auto at = std::find_if(graph.nodes.begin(), graph.nodes.end(),
                                 [](const NodeDesc& n) { return n.name == kDisplay; });
    graph.nodes.insert(at, added.begin(), added.end());
    findNode(graph, kDisplay)->inputs["color"] = color;
    if (addOutputs) {
        graph.outputs.push_back({"lit.####.exr", {color}, pointer, false});
        graph.outputs.push_back({"shadows.####.exr", shadowLayers, pointer, false});
    }
}

}  // namespace fp::io
