#pragma once
// Every JSON file framepass reads (config, preset, profile, camera sidecar, scene) goes through
// here: a folder or unreadable path, broken JSON and nesting deeper than limits::kMaxJsonDepth are
// usage errors that name the file. The depth limit stops a few hundred kilobytes of brackets from
// overflowing the stack in the recursive code that copies and walks the document.
#include "foundation/Error.h"
#include "foundation/Limits.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <istream>
#include <sstream>
#include <string>

namespace fp::io {

namespace detail {
struct JsonTooDeep {};
}  // namespace detail

/// Parses JSON (comments allowed) no deeper than limits::kMaxJsonDepth; `what` names the source
/// in errors ("config.json", "--set ssgi.quality").
inline nlohmann::json parseJsonLimited(std::istream& in, const std::string& what) {
    const nlohmann::json::parser_callback_t depthGuard =
        [](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
            if (depth >= limits::kMaxJsonDepth)  // depth counts from 0
                throw detail::JsonTooDeep{};
            return true;
        };
    try {
        return nlohmann::json::parse(in, depthGuard, true, /*ignore_comments=*/true);
    } catch (const detail::JsonTooDeep&) {
        throw UsageError(fmt::format("{}: JSON nested more than {} levels deep (the limit)", what,
                                     limits::kMaxJsonDepth));
    } catch (const nlohmann::json::exception& e) {
        // parse_error, and out_of_range for a number too large for a double (1e999).
        throw UsageError(fmt::format("{}: not valid JSON: {}", what, e.what()));
    }
}

inline nlohmann::json parseJsonLimited(const std::string& text, const std::string& what) {
    std::istringstream in(text);
    return parseJsonLimited(in, what);
}

/// Reads and parses the JSON file at `path`; `role` says what it is ("config", "camera sidecar").
inline nlohmann::json readJsonFile(const std::string& path, const std::string& role) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw UsageError(fmt::format("{}: is a folder, not a {} file", path, role));
    std::ifstream in(path);
    if (!in)
        throw UsageError(fmt::format("{}: cannot open the {}", path, role));
    return parseJsonLimited(in, path);
}

}  // namespace fp::io
