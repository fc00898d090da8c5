// A look-dev session shared between threads, under ASan and UBSan (`make fuzz` builds and runs it
// beside the fuzz targets): two threads run frames while the main thread sets cvars, reads the
// report and the cvars, plans other outputs and cancels, for a given time. A crash, a memory error
// or a lost setting fails it: after the race the session must run with the last value set and
// give the bits of a session made with that value.
//
//   SessionRace SOURCE_DIR SCRATCH_DIR SECONDS
#include "app/Capture.h"
#include "app/Session.h"
#include "foundation/Error.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>
#include <vector>

using namespace fp;

namespace {

const std::vector<std::string> kOutputs = {"ssgi_denoise.diffuse", "diffuse_indirect_composite.color"};

bool sameBits(const Image& a, const Image& b) {
    if (a.width() != b.width() || a.height() != b.height() || a.channelCount() != b.channelCount())
        return false;
    for (int c = 0; c < a.channelCount(); ++c)
        for (int y = 0; y < a.height(); ++y)
            if (std::memcmp(a.plane(c).row(y), b.plane(c).row(y), std::size_t(a.width()) * 4) != 0)
                return false;
    return true;
}

app::SetupOptions options(const std::string& config) {
    app::SetupOptions o;
    o.config = config;
    return o;
}

}  // namespace

int race(int argc, char** argv) {
    if (argc != 4) {
        std::cerr << "usage: SessionRace SOURCE_DIR SCRATCH_DIR SECONDS\n";
        return 2;
    }
    // Absolute: the config names its capture, and a config's relative paths are its folder's.
    const std::string source = argv[1], scratch = std::filesystem::absolute(argv[2]).string();
    const double seconds = std::atof(argv[3]);
    std::filesystem::create_directories(scratch);
    app::CaptureOptions c;
    c.scene = source + "/examples/cornell/scene.json";
    c.output = scratch + "/race.exr";
    c.width = 48;
    c.height = 32;
    c.lightSamples = 2;
    std::ostringstream quiet;
    app::captureScene(c, quiet);
    const std::string config = scratch + "/race.json";
    std::ofstream(config) << nlohmann::json{{"version", 1}, {"capture", c.output}}.dump();

    app::Session session(options(config));
    std::atomic<bool> stop{false};
    std::atomic<int> runs{0}, failures{0};
    std::vector<std::thread> runners;
    for (int t = 0; t < 2; ++t)
        runners.emplace_back([&] {
            while (!stop) {
                try {
                    session.run(1, kOutputs);
                    ++runs;
                } catch (const Cancelled&) {
                } catch (const std::exception& e) {
                    std::cerr << "a run failed: " << e.what() << "\n";
                    ++failures;
                    return;
                }
            }
        });
    int quality = 1, changes = 0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        quality = 1 + changes % 2;
        session.setCvar("r.SSGI.Quality", quality);
        if (session.cvarValue("r.SSGI.Quality") != quality) {
            std::cerr << "a setting read back wrong\n";
            ++failures;
        }
        (void)session.lastReport();
        (void)session.setup(changes % 3 ? kOutputs : std::vector<std::string>{"ssgi.hitMask"});
        if (changes % 7 == 0) session.cancel();
        ++changes;
    }
    stop = true;
    for (auto& t : runners) t.join();

    app::Session fresh(options(config));
    fresh.setCvar("r.SSGI.Quality", quality);
    const app::FrameResult expected = fresh.run(1, kOutputs), got = session.run(1, kOutputs);
    for (const auto& name : kOutputs)
        if (!sameBits(got.images.at(name), expected.images.at(name))) {
            std::cerr << name << ": the last setting (r.SSGI.Quality=" << quality
                      << ") was lost: the bits differ from a session made with it\n";
            ++failures;
        }
    std::cout << "SessionRace: " << runs << " runs and " << changes << " changes in " << seconds
              << " s, " << failures << " failures\n";
    return failures == 0 ? 0 : 1;
}

int main(int argc, char** argv) {
    try {
        return race(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "SessionRace: " << e.what() << "\n";
        return 1;
    }
}
