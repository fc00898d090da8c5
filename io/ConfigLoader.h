#pragma once
// Loads a run config (docs/config.md): JSON with comments, versioned, every key checked, every problem
// reported at once with its JSON pointer. A config without "passes" takes the whole chain of its
// engine's preset (configs/<engine>.json), so a user's config can be three lines.
#include "framework/Diagnostics.h"
#include "framework/GraphDesc.h"

#include <nlohmann/json.hpp>

#include <string>

namespace fp::io {

struct RunConfig {
    std::string path;     //!< the config file ("" when built in memory)
    std::string baseDir;  //!< relative paths in the config are relative to this folder
    std::string capture;  //!< capture file or frame pattern (resolved against baseDir)
    nlohmann::json profile = "canonical";
    std::string camera;   //!< optional camera sidecar (pattern allowed)
    std::string previous;  //!< the frame before a single capture (cur.exr + prev.exr), or ""
    std::string scene;    //!< optional scene JSON, for passes that need geometry
    std::string frames;   //!< optional frame spec
    std::string ocioConfig;  //!< "" = $OCIO, else the shipped configs/ocio/config.ocio
    std::string compression = "zip";
    std::string colorPrecision = "half";  //!< colour layers of EXR outputs: "half" or "float"
    int pngLevel = 1;  //!< zlib level of PNG outputs (io/PngWriter.h kDefaultPngLevel)
    std::string preset;  //!< the preset file that gave the chain, when the config has no passes
    GraphDesc graph;
    /// Problems found while reading; the planner reports them together with its own.
    std::vector<Diagnostic> errors;
};

/// Reads a config file. Unreadable JSON throws fp::UsageError; every other problem is listed in
/// RunConfig::errors for the planner to report with its own.
RunConfig loadRunConfig(const std::string& path);
/// Same, from parsed JSON (relative paths against `baseDir`).
RunConfig parseRunConfig(const nlohmann::json& j, const std::string& source,
                         const std::string& baseDir);

/// The folder of shipped presets and the OCIO config ($FRAMEPASS_CONFIG_DIR overrides it).
std::string configDirectory();

/// Parses a command-line value: JSON when it parses (3, true, "x"), else the raw string.
nlohmann::json parseCliValue(const std::string& text);

}  // namespace fp::io
