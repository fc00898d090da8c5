#pragma once
#include "foundation/Image.h"

#include <string>

namespace fp::io {

/// Writes a display-referred RGB image (values in [0, 1]) as an 8-bit PNG, atomically.
void writePng(const std::string& path, const Image& rgb);

}  // namespace fp::io

namespace fp::io {

/// The PNG file bytes of a display-referred RGB image (for embedding in an HTML report).
std::string encodePng(const Image& rgb);

}  // namespace fp::io
