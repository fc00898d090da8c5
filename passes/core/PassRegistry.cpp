#include "passes/core/PassRegistry.h"

namespace fp {

const PassType* PassRegistry::find(const std::string& id) const {
    for (const auto& t : mTypes)
        if (t.id == id) return &t;
    return nullptr;
}

std::vector<std::string> PassRegistry::ids() const {
    std::vector<std::string> ids;
    for (const auto& t : mTypes) ids.push_back(t.id);
    return ids;
}

}  // namespace fp
