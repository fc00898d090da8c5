// Fuzz target: an OBJ scene — the bytes are the .obj a fixed scene JSON names — loaded whole,
// meshes included, as `capture` and rt_shadows load it.
#include "fuzz/FuzzSupport.h"
#include "io/scene/SceneLoader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return fp::fuzz::expectCleanErrors([&] {
        const std::string obj = fp::fuzz::asFile(data, size, ".obj", "geometry");
        const std::string scene = fp::fuzz::asFile(nullptr, 0, ".json", "scene");
        std::ofstream(scene) << R"({"version": 1, "geometry": ")" << obj
                             << R"(", "camera": {"position": [0, 0, -5], "target": [0, 0, 0],
                                  "fovYDegrees": 40}, "lights": []})";
        fp::io::loadScene(scene, fp::io::SceneParts::All);
    });
}
