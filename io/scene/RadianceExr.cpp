#include "io/scene/RadianceExr.h"

#include "io/ExrReader.h"
#include "foundation/Error.h"

#include <cmath>
#include <optional>

namespace fp::io {

namespace {
[[noreturn]] void fail(const std::string& file, const std::string& where, const std::string& msg) {
    throw Error(fmt::format("{}: {}: {}", file, where, msg), ExitCode::Usage);
}
}  // namespace

Image readRadianceExr(const std::string& path, const std::string& file, const std::string& where) {
    std::optional<ExrReader> opened;
    try {
        opened.emplace(path);
    } catch (const Error& e) {  // missing, a folder, not an EXR: a bad scene, exit 2
        fail(file, where, e.what());
    }
    ExrReader& exr = *opened;
    std::vector<std::string> channels;
    for (const char* c : {"R", "G", "B"})
        if (exr.findChannel(c)) channels.push_back(c);
    if (channels.size() != 3) {
        if (!exr.findChannel("Y"))
            fail(file, where, path + " has neither R, G, B nor Y channels");
        channels = {"Y", "Y", "Y"};
    }
    Image image = exr.read(channels, {"R", "G", "B"});
    for (int c = 0; c < 3; ++c)
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x) {
                const float v = image.plane(c).at(x, y);
                if (!std::isfinite(v) || v < 0)
                    fail(file, where, fmt::format("{} has {} at pixel ({}, {}): radiance must be finite and ≥ 0",
                                                  path, v, x, y));
            }
    return image;
}

}  // namespace fp::io
