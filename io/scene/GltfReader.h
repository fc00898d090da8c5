#pragma once
// glTF 2.0 (.gltf/.glb) through tinygltf: meshes, metallic-roughness materials, cameras and
// KHR_lights_punctual lights, every index checked by its JSON pointer before it is followed.
#include "io/scene/SceneLoader.h"

#include <string>

namespace fp::io {

/// Reads the whole file into `sf` (meshes, materials, lights, and the first camera as the scene's
/// camera when the scene JSON names none). Throws fp::Error naming the file and JSON pointer.
void loadGltf(const std::string& path, SceneFile& sf);

}  // namespace fp::io
