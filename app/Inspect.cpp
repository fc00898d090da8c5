#include "app/Inspect.h"

#include "io/CameraIO.h"
#include "io/CaptureFiles.h"
#include "io/CaptureProfile.h"
#include "io/ExrReader.h"
#include "foundation/Error.h"

#include <OpenEXR/ImfHeader.h>

#include <fmt/ranges.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>
#include <set>

namespace fp::app {

namespace {
constexpr std::size_t kBandBytes = std::size_t(64) << 20;

const char* typeName(Imf::PixelType t) {
    return t == Imf::HALF ? "half" : (t == Imf::FLOAT ? "float" : "uint");
}

// One channel's statistics over its finite values, with NaN and infinities counted apart.
struct ChannelStats {
    double lo = INFINITY, hi = -INFINITY, sum = 0;
    uint64_t nan = 0, inf = 0, finite = 0;

    /// Adds a band of the channel's rows.
    void add(const Plane& plane) {
        for (int y = 0; y < plane.height(); ++y)
            for (int x = 0; x < plane.width(); ++x) {
                const float v = plane.at(x, y);
                if (std::isnan(v)) ++nan;
                else if (std::isinf(v)) ++inf;
                else {
                    lo = std::min(lo, double(v));
                    hi = std::max(hi, double(v));
                    sum += v;
                    ++finite;
                }
            }
    }
};
}  // namespace

nlohmann::json inspectCapture(const std::string& capture, const std::string& profileName,
                              const std::string& camera) {
    const io::CaptureProfile profile = io::CaptureProfile::load(profileName);
    io::CaptureFiles files(capture, profile);
    nlohmann::json j;
    j["file"] = files.capturePath();
    j["profile"] = profile.name();
    j["width"] = files.extent().width;
    j["height"] = files.extent().height;
    j["channels"] = nlohmann::json::array();
    std::set<std::string> layers;
    for (const auto& [key, constReader] : files.files()) {
        // Statistics read pixels; the file stays the one CaptureFiles opened.
        io::ExrReader reader(constReader->path());
        // A part's channels are read together: OpenEXR decompresses a part's pixel blocks
        // whole, so reading its channels one by one would decompress the part once a channel.
        // A band of rows at a time (about kBandBytes, whole compression blocks) keeps memory
        // bounded whatever the file's size: a 16384² capture streams through 64 MiB.
        const std::vector<io::ExrChannel>& channels = reader.channels();
        std::vector<ChannelStats> stats(channels.size());
        for (std::size_t first = 0; first < channels.size();) {
            std::size_t end = first;
            std::vector<const io::ExrChannel*> part;
            std::vector<std::string> names;
            for (; end < channels.size() && channels[end].part == channels[first].part; ++end) {
                part.push_back(&channels[end]);
                names.push_back(fmt::format("c{}", end - first));
            }
            const auto dw = reader.header(channels[first].part).dataWindow();
            const Extent e{dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1};
            const std::size_t rowBytes = imageBytes(Extent{e.width, 1}, int(part.size()));
            const int band = std::max(64, int(kBandBytes / std::max<std::size_t>(rowBytes, 1)) / 64 * 64);
            for (int y = 0; y < e.height; y += band) {
                const Image img = reader.readRows(part, names, y, std::min(band, e.height - y));
                tbb::parallel_for(std::size_t(0), part.size(), [&](std::size_t i) {
                    stats[first + i].add(img.plane(int(i)));
                });
            }
            first = end;
        }
        for (std::size_t i = 0; i < channels.size(); ++i) {
            const io::ExrChannel& c = channels[i];
            const ChannelStats& st = stats[i];
            // In a mip chain every part repeats the channel names: show "<part>/<channel>".
            const Imf::Header& h = reader.header(c.part);
            std::string shown = reader.partCount() > 1 && h.hasName()
                                    ? h.name() + "/" + c.name : c.name;
            if (!key.empty()) shown = key + ":" + shown;
            layers.insert(c.name.substr(0, c.name.rfind('.') == std::string::npos
                                               ? 0 : c.name.rfind('.')));
            j["channels"].push_back({{"name", shown}, {"type", typeName(c.type)},
                                     {"part", c.part},
                                     {"buffer", files.bufferOfChannel(key, c.name)},
                                     {"min", st.finite ? st.lo : 0.0},
                                     {"max", st.finite ? st.hi : 0.0},
                                     {"mean", st.finite ? st.sum / st.finite : 0.0},
                                     {"nan", st.nan}, {"inf", st.inf}});
        }
    }
    j["buffers"] = nlohmann::json::object();
    j["warnings"] = nlohmann::json::object();
    for (const auto& b : files.availableBuffers()) {
        j["buffers"][b] = files.describe(b);
        if (const io::BufferMapping* m = files.mappingFor(b); m && !m->warning.empty())
            j["warnings"][b] = m->warning;
    }
    // What the profile leaves out on purpose, where the capture has it.
    j["unmapped"] = nlohmann::json::object();
    for (const auto& [layer, why] : profile.unmapped())
        for (const auto& l : layers)
            if (l.rfind(layer, 0) == 0) j["unmapped"][l] = why;
    if (!profile.filePattern().empty()) {
        // A multi-file capture: the files of the same base no mapping reads.
        namespace fs = std::filesystem;
        const fs::path base(files.capturePath());
        const std::string stem = base.filename().string() + "_";
        std::set<std::string> opened;
        for (const auto& [key, r] : files.files()) opened.insert(key);
        std::error_code ec;
        const fs::path dir = base.has_parent_path() ? base.parent_path() : fs::path(".");
        for (const auto& e : fs::directory_iterator(dir, ec)) {
            const std::string name = e.path().filename().string();
            if (name.rfind(stem, 0) != 0 || e.path().extension() != ".exr") continue;
            const std::string key = name.substr(stem.size(), name.size() - stem.size() - 4);
            if (opened.count(key)) continue;
            const auto why = profile.unmapped().find(key);
            j["unmapped"][name] = why != profile.unmapped().end()
                                      ? why->second
                                      : "the profile maps no buffer to it";
        }
    }
    io::CameraLookup lookup;
    lookup.sidecar = camera;
    lookup.capturePath = files.capturePath();
    lookup.header = &files.primary().header();
    lookup.extent = files.extent();
    lookup.profileUnits = profile.sceneUnitsPerMeter();
    if (auto found = io::findCamera(lookup)) {
        j["camera"] = io::cameraViewToJson(found->camera.current);
        j["camera"]["sceneUnitsPerMeter"] = found->camera.sceneUnitsPerMeter;
        j["camera"]["source"] = found->source;
        j["camera"]["assumptions"] = found->assumptions;
        if (found->camera.previous)
            j["camera"]["previous"] = io::cameraViewToJson(*found->camera.previous);
    }
    j["files"] = files.files().size();
    int parts = 0;
    for (const auto& f : files.files()) parts += f.second->partCount();
    j["parts"] = parts;
    return j;
}

std::string inspectionText(const nlohmann::json& j) {
    std::string out;
    out += fmt::format("{}: {}×{}, {} file(s), {} part(s), {} channels\n",
                       j["file"].get<std::string>(), j["width"].get<int>(), j["height"].get<int>(),
                       j["files"].get<int>(), j["parts"].get<int>(), j["channels"].size());
    out += fmt::format("  {:<36} {:<6} {:<16} {:>12} {:>12} {:>12} {:>6} {:>6}\n",
                             "channel", "type", "buffer", "min", "max", "mean", "NaN", "Inf");
    for (const auto& c : j["channels"])
        out += fmt::format("  {:<36} {:<6} {:<16} {:>12.5g} {:>12.5g} {:>12.5g} {:>6} {:>6}\n",
                                 c["name"].get<std::string>(), c["type"].get<std::string>(),
                                 c["buffer"].get<std::string>(), c["min"].get<double>(),
                                 c["max"].get<double>(), c["mean"].get<double>(),
                                 c["nan"].get<uint64_t>(), c["inf"].get<uint64_t>());
    out += fmt::format("buffers ({} profile):\n", j["profile"].get<std::string>());
    for (const auto& [b, how] : j["buffers"].items())
        out += fmt::format("  {:<16} ← {}\n", b,
                                 fmt::join(how.get<std::vector<std::string>>(), " "));
    for (const auto& [b, why] : j["warnings"].items())
        out += fmt::format("  warning: {}: {}\n", b, why.get<std::string>());
    for (const auto& [l, why] : j["unmapped"].items())
        out += fmt::format("  not read: {} ({})\n", l, why.get<std::string>());
    if (j.contains("camera")) {
        const auto& c = j["camera"];
        out += fmt::format("camera ({}): position [{:.6f}, {:.6f}, {:.6f}], forward "
                                 "[{:.4f}, {:.4f}, {:.4f}], fovY {:.3f}°, near {}, {} "
                                 "units/m{}\n",
                                 c["source"].get<std::string>(),
                                 c["position"][0].get<double>(), c["position"][1].get<double>(),
                                 c["position"][2].get<double>(), c["forward"][0].get<double>(),
                                 c["forward"][1].get<double>(), c["forward"][2].get<double>(),
                                 c["fovYDegrees"].get<double>(), c["near"].get<double>(),
                                 c["sceneUnitsPerMeter"].get<double>(),
                                 c.contains("previous") ? ", previous camera present" : "");
        for (const auto& a : c["assumptions"])
            out += "  assumed: " + a.get<std::string>() + "\n";
    } else {
        out += "camera: none (no sidecar <capture>.camera.json, and the header has no "
                     "framepass, worldToNDC or unreal/camera attributes)\n";
    }
    return out;
}

}  // namespace fp::app
