#pragma once
// Writes multi-layer OpenEXR: ZIP by default, data layers as float32, colour as half (values
// beyond half's range saturate instead of becoming Inf), no timestamp in the header so reruns are
// byte-identical, and always through a temporary file renamed into place so a killed job never
// leaves a complete-looking file.
#include "foundation/Camera.h"
#include "foundation/Image.h"

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace fp::io {

struct ExrLayer {
    std::string name;       //!< layer prefix; channels are written as name.<channel>
    const Image* image;
    bool half = false;      //!< store as half (colour) rather than float32 (data)
};

/// One part of the file. A file with several parts has one per mip level (HZB, reduced colour).
struct ExrPart {
    std::string name;
    std::vector<ExrLayer> layers;
    int displayWidth = 0, displayHeight = 0;  //!< set by writeExr: the first part's size
};

struct ExrMetadata {
    std::optional<FrameCamera> camera;
    std::optional<int64_t> frame;
    std::map<std::string, std::string> strings;
};

enum class ExrCompression { Zip, None, Piz, Zips };

/// Parses "zip", "none", "piz" or "zips"; throws fp::UsageError otherwise.
ExrCompression parseCompression(const std::string& name);

/// The bytes of the EXR file `parts` make: colour converted to half and every chunk compressed
/// on OpenEXR's thread pool, in memory (no file is touched). OpenEXR's errors become fp::Error
/// naming `path`, the file the bytes are for.
std::vector<char> encodeExr(const std::string& path, const std::vector<ExrPart>& parts,
                            const ExrMetadata& metadata,
                            ExrCompression compression = ExrCompression::Zip);
/// encodeExr's bytes written to `path` atomically (io/SafeFiles.h).
void writeExr(const std::string& path, const std::vector<ExrPart>& parts,
              const ExrMetadata& metadata, ExrCompression compression = ExrCompression::Zip);

/// Moves `tmp` onto `path` (same folder, so the rename is atomic).
void commitFile(const std::string& tmp, const std::string& path);
/// A temporary name in the same folder as `path`.
std::string temporaryPathFor(const std::string& path);

}  // namespace fp::io
