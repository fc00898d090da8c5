#include "io/ExrLayers.h"

#include "foundation/Error.h"
#include "foundation/Suggest.h"

#include <algorithm>

namespace fp::io {

namespace {
int displayRank(const std::string& suffix) {
    static const std::vector<std::string> kOrder = {"R", "G", "B", "A", "X", "Y", "Z"};
    auto it = std::find(kOrder.begin(), kOrder.end(), suffix);
    return it == kOrder.end() ? int(kOrder.size()) : int(it - kOrder.begin());
}
}  // namespace

std::vector<ExrLayerInfo> listLayers(const ExrReader& file) {
    std::vector<ExrLayerInfo> layers;
    for (const auto& c : file.channels()) {
        const auto dot = c.name.rfind('.');
        const std::string layer = dot == std::string::npos ? "" : c.name.substr(0, dot);
        const std::string suffix = dot == std::string::npos ? c.name : c.name.substr(dot + 1);
        auto it = std::find_if(layers.begin(), layers.end(),
                               [&](const ExrLayerInfo& l) { return l.name == layer; });
        if (it == layers.end()) {
            layers.push_back({layer, {}, {}});
            it = layers.end() - 1;
        }
        // Later parts of a mip chain repeat the names: keep the first (mip 0).
        if (std::find(it->suffixes.begin(), it->suffixes.end(), suffix) != it->suffixes.end())
            continue;
        it->channels.push_back(&c);
        it->suffixes.push_back(suffix);
    }
    for (auto& l : layers) {
        std::vector<std::size_t> order(l.channels.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return displayRank(l.suffixes[a]) < displayRank(l.suffixes[b]);
        });
        ExrLayerInfo sorted{l.name, {}, {}};
        for (std::size_t i : order) {
            sorted.channels.push_back(l.channels[i]);
            sorted.suffixes.push_back(l.suffixes[i]);
        }
        l = sorted;
    }
    return layers;
}

ExrLayerInfo findLayer(const ExrReader& file, const std::string& name) {
    const auto layers = listLayers(file);
    std::vector<std::string> names;
    for (const auto& l : layers) {
        if (l.name == name) return l;
        names.push_back(l.name.empty() ? "\"\"" : l.name);
    }
    throw UsageError(fmt::format("{}: no layer '{}'{}; layers: {}", file.path(), name,
                                 didYouMean(name, names), fmt::join(names, ", ")));
}

Image readLayer(ExrReader& file, const ExrLayerInfo& layer) {
    return file.read(layer.channels, layer.suffixes);
}

}  // namespace fp::io
