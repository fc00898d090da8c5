#pragma once
// 8-bit PNG previews of display-referred RGB images, encoded in memory by OpenImageIO.
#include "foundation/Image.h"

#include <string>

namespace fp::io {

/// zlib's level for a PNG (0 = stored, 9 = smallest): the pixels are the same at every level.
/// framepass's default is 1, the fastest that compresses: a 1080p preview encodes 2.7× faster
/// than at zlib's own default of 6, for a file a tenth larger (docs/config.md).
constexpr int kDefaultPngLevel = 1;

/// The PNG file's bytes of a display-referred RGB image (values clamped to [0, 1], rounded to
/// 8 bits). `path`: the file they are for, named in errors ("" = none: bytes for a page).
std::string encodePng(const Image& rgb, int zlibLevel = kDefaultPngLevel,
                      const std::string& path = "");

/// encodePng's bytes written to `path` atomically (io/SafeFiles.h).
void writePng(const std::string& path, const Image& rgb, int zlibLevel = kDefaultPngLevel);

}  // namespace fp::io
