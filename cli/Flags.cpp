// The command-line flags several subcommands share, registered on CLI11 subcommands; what they
// fill are the application library's option structs.
#include "cli/Flags.h"

#include "app/ErrorBreakdown.h"
#include "foundation/Error.h"

#include <functional>


namespace fp::cli {

const CLI::Validator& nonEmptyPath() {
    static const CLI::Validator check(
        [](std::string& value) {
            return value.empty() ? std::string("an empty path names no file or folder") : std::string();
        },
        "PATH");
    return check;
}

namespace {
// A value that cannot be read, found while CLI11 parses: its error, as every other flag's.
void asParseError(const std::function<void()>& read) {
    try {
        read();
    } catch (const UsageError& e) {
        throw CLI::ValidationError(e.what());
    }
}
}  // namespace

void addSetupOptions(CLI::App& sub, app::SetupOptions& o) {
    sub.add_option("config", o.config, "run config (JSON)")->required();
    // The command line is where settings are text: each becomes a typed value as it is read.
    sub.add_option_function<std::vector<std::string>>(
                   "--cvar",
                   [&o](const std::vector<std::string>& texts) {
                       for (const auto& t : texts) asParseError([&] { o.settings.setCvarText(t); });
                   },
                   "set an Unreal cvar as the console takes it: --cvar \"r.SSGI.Quality 4\" or "
                   "--cvar r.SSGI.Quality=4 (names in any case)");
    sub.add_option("--cvars", o.cvarFiles,
                   "read cvars from an Unreal .ini ([SystemSettings] / [ConsoleVariables], ; "
                   "comments), such as the snippet tune prints; --cvar wins over it")
        ->check(CLI::ExistingFile);
    sub.add_option_function<std::vector<std::string>>(
        "--set",
        [&o](const std::vector<std::string>& texts) {
            for (const auto& t : texts) asParseError([&] { o.settings.setParamText(t); });
        },
        "set a pass parameter, e.g. --set hzb.halfPrecision=false");
    sub.add_option_function<std::vector<std::string>>(
        "--input",
        [&o](const std::vector<std::string>& texts) {
            for (const auto& t : texts) asParseError([&] { o.settings.setInputText(t); });
        },
        "rebind a pass's input to another source, e.g. --input gi.source=rtgi.diffuse (a pass "
        "output PASS.PORT or capture:Buffer)");
    sub.add_option("--dump", o.dumps, "also write PASS.PORT (or 'all') to <out>/dump/");
    sub.add_option("--frames", o.frames, "frame spec (overrides the config), e.g. 1001-1010");
    sub.add_option("--capture", o.capture,
                   "capture file or frame pattern (overrides the config's \"capture\"; relative "
                   "to the working directory)");
    sub.add_option("--previous", o.previous,
                   "the previous frame's capture, for a single capture that is not a numbered "
                   "sequence (cur.exr with prev.exr): temporal passes reproject it (overrides the "
                   "config's \"previous\")")
        ->check(nonEmptyPath());
    sub.add_option("--profile", o.profile,
                   "capture profile, a name or FILE.json (overrides the config's \"profile\")");
    sub.add_option("--device", o.device,
                   "cpu, or cuda: the passes with a CUDA kernel run on the GPU, images stay "
                   "there between them (overrides the config's \"device\")")
        ->check(CLI::IsMember({"cpu", "cuda"}));
    sub.add_flag("--allow-unknown-cvars", o.allowUnknownCvars,
                 "a cvar framepass does not know (--cvar or the config's \"cvars\") is a "
                 "warning instead of an error");
}


void addSweepOption(CLI::App& sub, std::vector<app::SweepAxis>& axes, const std::string& help) {
    sub.add_option_function<std::vector<std::string>>(
        "--sweep",
        [&axes](const std::vector<std::string>& texts) {
            for (const auto& t : texts) asParseError([&] { axes.push_back(app::parseSweep(t)); });
        },
        help);
}

void addTimingOptions(CLI::App& sub, app::BenchOptions& o) {
    sub.add_option("--runs", o.runs, fmt::format("timed runs per setting (default {})", o.runs))
        ->check(CLI::Range(1, 1000));
    sub.add_option("--warmup", o.warmup, fmt::format("untimed runs first (default {})", o.warmup))
        ->check(CLI::Range(0, 100));
}

void addDecomposeRaysOption(CLI::App& sub, int& rays, const std::string& help) {
    sub.add_option("--decompose-rays", rays, help)->check(CLI::Range(0, app::kMaxBreakdownRays));
}

void addMaxMemoryOption(CLI::App& sub, std::string& value) {
    sub.add_option("--max-memory", value,
                   "refuse to start when the plan's predicted peak of image memory is above "
                   "this (8G, 512M, bytes; default 3/4 of the memory available, within the "
                   "job's cgroup limit)");
}

}  // namespace fp::cli
