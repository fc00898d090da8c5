#pragma once
// Passes that work on one light (rt_shadows, shadow_denoise, deferred_lighting) name it with their
// `light` parameter; an empty name means the scene's only light.
#include "foundation/Error.h"
#include "foundation/Scene.h"
#include "foundation/Suggest.h"

#include <string>
#include <vector>

namespace fp {

inline const Light& namedLight(const std::vector<Light>& lights, const std::string& name) {
    if (name.empty()) {
        FP_CHECK(lights.size() == 1,
                 "the scene has {} lights: set the pass's 'light' parameter to one of them",
                 lights.size());
        return lights.front();
    }
    for (const Light& l : lights)
        if (l.name == name)
            return l;
    const std::vector<std::string> names = lightNames(lights);
    throw Error(fmt::format("no light named '{}' in the scene{}; lights: [{}]", name,
                            didYouMean(name, names), fmt::join(names, ", ")));
}

}  // namespace fp
