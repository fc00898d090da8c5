#pragma once
// Radiance maps a scene names (a sky light's lat-long map, a reflection capture's cubemap): an RGB
// or Y EXR read whole, every pixel checked finite and ≥ 0.
#include "foundation/Image.h"

#include <string>

namespace fp::io {

/// Reads `path`; errors (missing, unreadable, not an EXR, no R G B or Y channels, a pixel that is
/// not finite or negative) name the scene `file` and the key `where` that named it.
Image readRadianceExr(const std::string& path, const std::string& file, const std::string& where);

}  // namespace fp::io
