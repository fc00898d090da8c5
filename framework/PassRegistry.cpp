#include "framework/PassRegistry.h"

#include "foundation/Error.h"

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

void Pass::executeCuda(PassContext&) {
    throw Error("internal: executeCuda called on a pass without a CUDA kernel");
}

}  // namespace fp
