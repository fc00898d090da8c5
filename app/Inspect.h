#pragma once
// What a capture holds — its channels with their statistics, the buffers its profile reads from
// them, what the profile leaves out, its camera — as `framepass inspect` prints it (and --json
// gives it).
#include <nlohmann/json.hpp>

#include <string>

namespace fp::app {

/// Reads `capture` (multi-file profiles: the base or any one of its files) through profile
/// `profileName` (a name or FILE.json), a band of rows at a time; `camera`: a sidecar to use
/// instead of <capture>.camera.json or the header ("" = those). The JSON `inspect --json` prints.
nlohmann::json inspectCapture(const std::string& capture, const std::string& profileName,
                              const std::string& camera);

/// The table `inspect` prints for inspectCapture's JSON.
std::string inspectionText(const nlohmann::json& j);

}  // namespace fp::app
