#pragma once
// `framepass sheet`: every buffer of a capture (or every layer of every EXR in a folder, such as a
// run's dumps) as one labelled tile of a PNG contact sheet, like `oiiotool --mosaic` or Nuke's
// ContactSheet. Colour goes through the OCIO display transform the display pass uses; data is
// mapped over its own range, printed on the tile (metrics/BufferPreview.h).
#include <nlohmann/json.hpp>

#include <string>

namespace fp::app {

struct SheetOptions {
    std::string input;   //!< a capture EXR, or a folder of EXRs
    std::string output;  //!< the PNG written
    std::string profile = "canonical", ocioConfig;
    int columns = 0;  //!< 0 = ⌈√tiles⌉
    int tile = 0;     //!< tile width; 0 = the image width, at most 256
};

/// Writes the sheet and returns what it holds: the sheet's size and layout, and every tile's
/// file, layer, channels, buffer, kind, label and range (`sheet --json`).
nlohmann::json writeSheet(const SheetOptions& opt);

}  // namespace fp::app
