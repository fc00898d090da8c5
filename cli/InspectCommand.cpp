// framepass inspect: what a capture holds — channels, their buffers, camera, statistics.
#include "cli/Commands.h"
#include "io/CameraIO.h"
#include "io/CaptureProfile.h"
#include "io/ExrReader.h"
#include "passes/core/Error.h"

#include <OpenEXR/ImfHeader.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>

namespace fp::cli {

namespace {
const char* typeName(Imf::PixelType t) {
    return t == Imf::HALF ? "half" : (t == Imf::FLOAT ? "float" : "uint");
}
}  // namespace

Command addInspectCommand(CLI::App& app) {
    struct Options {
        std::string capture, profile = "canonical";
        bool json = false;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand("inspect", "list a capture's channels, buffers, camera and "
                                                  "per-channel statistics");
    sub->add_option("capture", opt->capture, "capture EXR")->required();
    sub->add_option("--profile", opt->profile, "capture profile (canonical)");
    sub->add_flag("--json", opt->json, "machine-readable output");

    return [opt]() {
        io::ExrReader reader(opt->capture);
        const io::CaptureProfile profile = io::CaptureProfile::byName(opt->profile);
        nlohmann::json j;
        j["file"] = opt->capture;
        j["width"] = reader.extent().width;
        j["height"] = reader.extent().height;
        j["parts"] = reader.partCount();
        j["channels"] = nlohmann::json::array();
        for (const auto& c : reader.channels()) {
            // One channel at a time keeps memory at one plane whatever the file's size.
            const Image img = reader.read(std::vector<const io::ExrChannel*>{&c}, {"v"});
            double lo = INFINITY, hi = -INFINITY, sum = 0;
            uint64_t nan = 0, inf = 0, finite = 0;
            for (int y = 0; y < img.height(); ++y)
                for (int x = 0; x < img.width(); ++x) {
                    const float v = img.plane(0).at(x, y);
                    if (std::isnan(v)) ++nan;
                    else if (std::isinf(v)) ++inf;
                    else {
                        lo = std::min(lo, double(v));
                        hi = std::max(hi, double(v));
                        sum += v;
                        ++finite;
                    }
                }
            // In a mip chain every part repeats the channel names: show "<part>/<channel>".
            const Imf::Header& h = reader.header(c.part);
            const std::string shown = reader.partCount() > 1 && h.hasName()
                                          ? h.name() + "/" + c.name : c.name;
            j["channels"].push_back({{"name", shown}, {"type", typeName(c.type)}, {"part", c.part},
                                     {"buffer", profile.bufferOfChannel(c.name)},
                                     {"min", finite ? lo : 0.0}, {"max", finite ? hi : 0.0},
                                     {"mean", finite ? sum / finite : 0.0}, {"nan", nan},
                                     {"inf", inf}});
        }
        const auto buffers = profile.availableBuffers(reader);
        j["buffers"] = std::vector<std::string>(buffers.begin(), buffers.end());
        if (auto cam = io::readCameraAttributes(reader.header(), reader.extent())) {
            j["camera"] = io::cameraViewToJson(cam->current);
            j["camera"]["sceneUnitsPerMeter"] = cam->sceneUnitsPerMeter;
            if (cam->previous) j["camera"]["previous"] = io::cameraViewToJson(*cam->previous);
        }
        if (opt->json) {
            std::cout << j.dump(2) << "\n";
            return 0;
        }
        std::cout << fmt::format("{}: {}×{}, {} part(s), {} channels\n", opt->capture,
                                 reader.extent().width, reader.extent().height, reader.partCount(),
                                 reader.channels().size());
        std::cout << fmt::format("  {:<36} {:<6} {:<16} {:>12} {:>12} {:>12} {:>6} {:>6}\n",
                                 "channel", "type", "buffer", "min", "max", "mean", "NaN", "Inf");
        for (const auto& c : j["channels"])
            std::cout << fmt::format("  {:<36} {:<6} {:<16} {:>12.5g} {:>12.5g} {:>12.5g} {:>6} {:>6}\n",
                                     c["name"].get<std::string>(), c["type"].get<std::string>(),
                                     c["buffer"].get<std::string>(), c["min"].get<double>(),
                                     c["max"].get<double>(), c["mean"].get<double>(),
                                     c["nan"].get<uint64_t>(), c["inf"].get<uint64_t>());
        std::cout << fmt::format("buffers ({} profile): {}\n", profile.name(),
                                 fmt::join(buffers, ", "));
        if (j.contains("camera")) {
            const auto& c = j["camera"];
            std::cout << fmt::format("camera: position [{:.6f}, {:.6f}, {:.6f}], forward [{:.4f}, "
                                     "{:.4f}, {:.4f}], fovY {:.3f}°, near {}, {} units/m{}\n",
                                     c["position"][0].get<double>(), c["position"][1].get<double>(),
                                     c["position"][2].get<double>(), c["forward"][0].get<double>(),
                                     c["forward"][1].get<double>(), c["forward"][2].get<double>(),
                                     c["fovYDegrees"].get<double>(), c["near"].get<double>(),
                                     c["sceneUnitsPerMeter"].get<double>(),
                                     c.contains("previous") ? ", previous camera present" : "");
        } else {
            std::cout << "camera: none in the header (give a sidecar <capture>.camera.json)\n";
        }
        return 0;
    };
}

}  // namespace fp::cli
