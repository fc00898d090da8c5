#pragma once
// The layers of an EXR file as a person names them: "Truth.AO" for Truth.AO.Y, "pass.port"
// for pass.port.R/G/B, with channels in display order (R G B A, X Y Z) rather than the
// alphabetical order EXR stores them in. Mip chains written one part per mip list their mip 0.
#include "io/ExrReader.h"

#include <string>
#include <vector>

namespace fp::io {

struct ExrLayerInfo {
    std::string name;                         //!< "" for unprefixed channels (R, G, B)
    std::vector<const ExrChannel*> channels;  //!< in display order
    std::vector<std::string> suffixes;        //!< "R", "G", ...
};

std::vector<ExrLayerInfo> listLayers(const ExrReader& file);

/// The layer called `name`; throws fp::UsageError listing the file's layers (with a
/// did-you-mean) when there is none.
ExrLayerInfo findLayer(const ExrReader& file, const std::string& name);

Image readLayer(ExrReader& file, const ExrLayerInfo& layer);

}  // namespace fp::io
