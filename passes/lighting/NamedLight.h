#pragma once
// Passes that work on one light (rt_shadows, shadow_denoise, deferred_lighting) name it with their
// `light` parameter; an empty name means the scene's only light.
#include "passes/core/Error.h"
#include "passes/core/Scene.h"
#include "passes/core/Suggest.h"

#include <string>
#include <vector>

namespace fp {

inline const Light& namedLight(const Scene& scene, const std::string& name) {
    if (name.empty()) {
        FP_CHECK(scene.lights.size() == 1,
                 "the scene has {} lights: set the pass's 'light' parameter to one of them",
                 scene.lights.size());
        return scene.lights.front();
    }
    if (const Light* l = scene.findLight(name)) return *l;
    std::vector<std::string> names;
    for (const Light& l : scene.lights) names.push_back(l.name);
    throw Error(fmt::format("no light named '{}' in the scene{}; lights: [{}]", name,
                            didYouMean(name, names), fmt::join(names, ", ")));
}

}  // namespace fp
