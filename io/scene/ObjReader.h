#pragma once
// OBJ/MTL geometry through tinyobjloader: meshes with their materials (Kd, Ke, Pr, Pm), and vertex
// normals smoothed by angle where the file has none.
#include "foundation/Scene.h"

#include <optional>
#include <string>

namespace fp::io {

/// Appends the file's meshes and materials to `scene`. With `smoothAngleDegrees`, an OBJ without
/// normals gets vertex normals smoothed across faces that meet at less than that angle (else it
/// renders faceted). Throws fp::Error naming the file on bad input.
void loadObj(const std::string& path, Scene& scene, std::optional<float> smoothAngleDegrees);

}  // namespace fp::io
