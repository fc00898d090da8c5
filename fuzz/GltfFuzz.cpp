// Fuzz target: a glTF 2.0 scene (.gltf JSON with embedded buffers; seeds from examples/hard),
// loaded whole through a fixed scene JSON: meshes, nodes, cameras and KHR_lights_punctual.
#include "fuzz/FuzzSupport.h"
#include "io/scene/SceneLoader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return fp::fuzz::expectCleanErrors([&] {
        const std::string gltf = fp::fuzz::asFile(data, size, ".gltf", "geometry");
        const std::string scene = fp::fuzz::asFile(nullptr, 0, ".json", "scene");
        std::ofstream(scene) << R"({"version": 1, "geometry": ")" << gltf << R"("})";
        fp::io::loadScene(scene, fp::io::SceneParts::All);
    });
}
