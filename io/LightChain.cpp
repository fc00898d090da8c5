#include "io/LightChain.h"

#include "passes/core/Error.h"

#include <algorithm>

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

void addLightPasses(GraphDesc& graph, const std::vector<Light>& lights, bool addOutputs) {
    NodeDesc* composite = findNode(graph, kComposite);
    FP_ASSERT(composite && findNode(graph, kDisplay));  // every preset chain has both
    if (lights.empty()) return;
    composite->inputs["sceneColor"] = "capture:Emissive";
    const std::string pointer = composite->pointer;

    std::vector<NodeDesc> added;
    std::string color = std::string(kComposite) + ".color";
    std::vector<std::string> shadowLayers;
    const std::vector<std::string> ids = lightIdentifiers(lights);
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const std::string& id = ids[i];
        const nlohmann::json params = {{"light", lights[i].name}};
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
