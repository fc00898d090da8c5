// framepass run: execute the chain over the frames and write outputs, dumps and a report.
#include "cli/Commands.h"
#include "cli/Invocation.h"
#include "cli/RunSession.h"
#include "io/CaptureSource.h"
#include "io/OutputWriter.h"
#include "passes/core/Error.h"
#include "passes/core/Executor.h"

#include <fmt/chrono.h>

#include <chrono>
#include <filesystem>
#include <set>
#include <fstream>
#include <iostream>
#include <set>

namespace fp::cli {

namespace {
// Warm-up frames produce history only.
class DiscardSink final : public FrameSink {
public:
    void write(const OutputDesc&, const std::vector<OutputLayer>&, const FrameInfo&) override {}
};

// The `count` frames before the first, spaced like the sequence (its first step, else 1), that
// have a capture on disk (a sequence's start cuts the warm-up short).
std::vector<int> warmupFrames(const RunSession& session, int count) {
    const auto& frames = session.frames();
    if (count <= 0 || frames.empty())
        return {};
    const int step = frames.size() > 1 ? std::max(1, frames[1] - frames[0]) : 1;
    std::vector<int> out;
    for (int k = count; k >= 1; --k) {
        const int f = frames.front() - k * step;
        if (std::filesystem::exists(session.capturePath(f)))
            out.push_back(f);
    }
    return out;
}

// One input file of the report: what it was, where, how big and when it was last changed, so a
// report says exactly which bytes produced the outputs.
nlohmann::json inputFile(const std::string& role, const std::string& path) {
    namespace fs = std::filesystem;
    nlohmann::json j = {{"role", role}, {"path", path}};
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    if (ec) {
        j["missing"] = true;
        return j;
    }
    j["bytes"] = bytes;
    const auto written = fs::last_write_time(path, ec);
    if (!ec) {
        const auto sys = std::chrono::file_clock::to_sys(written);
        const auto seconds = std::chrono::floor<std::chrono::seconds>(sys);
        j["mtime"] = fmt::format("{:%Y-%m-%dT%H:%M:%S}Z",
                                 fmt::gmtime(std::chrono::system_clock::to_time_t(seconds)));
        j["mtimeNs"] =
            std::chrono::duration_cast<std::chrono::nanoseconds>(sys.time_since_epoch()).count();
    }
    return j;
}

}  // namespace

Command addRunCommand(CLI::App& app) {
    struct Options {
        SessionOptions session;
        std::string outputDir = "out", report;
        bool strict = false;
        int warmupFrames = 0;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand("run", "run the chain and write the requested outputs");
    opt->session.addTo(*sub);
    sub->add_option("-o,--output-dir", opt->outputDir, "folder for outputs (default: out)");
    sub->add_option("--report", opt->report, "write a JSON report: per-pass time and work counts");
    sub->add_flag("--strict", opt->strict,
                  "fail on NaN/Inf/negative input pixels instead of "
                  "sanitizing them");
    sub->add_option("--warmup-frames", opt->warmupFrames,
                    "run N frames before the first one (writing nothing) so temporal passes "
                    "start with history: a chunked farm run then equals a sequential one")
        ->check(CLI::Range(0, 100000));

    return [opt]() {
        const RunSession session(opt->session);
        const Plan& plan = session.plan();
        for (const auto& w : plan.warnings)
            logWarning(fmt::format("{}: {}", w.pointer, w.message));

        io::OutputWriter::Options wo;
        wo.outputDir = opt->outputDir;
        wo.compression = io::parseCompression(session.config().compression);
        wo.protectedPaths.insert(opt->session.config);
        for (int f : session.frames())
            wo.protectedPaths.insert(session.capturePath(f));
        io::OutputWriter writer(wo);

        const Invocation& inv = invocation();
        nlohmann::json report = {
            {"framepass", {{"version", inv.version}}},
            {"commandLine", inv.commandLine()},
            {"arguments", inv.arguments},
            {"threads", {{"requested", inv.threadsRequested}, {"used", inv.threads}}},
            {"config", opt->session.config},
            {"frames", nlohmann::json::array()}};
        // Every file read, once, in the order first read.
        nlohmann::json inputs = nlohmann::json::array();
        std::set<std::string> listed;
        auto addInput = [&](const std::string& role, const std::string& path) {
            if (!path.empty() && listed.insert(role + "\n" + path).second)
                inputs.push_back(inputFile(role, path));
        };
        addInput("config", opt->session.config);
        addInput("preset", session.config().preset);
        const auto& frames = session.frames();
        HistoryStore history;
        std::set<std::string> notesShown;  // each assumption once, not once per frame
        // Warm-up: the frames before the first, at the sequence's step, that exist on disk.
        const std::vector<int> warmup = warmupFrames(session, opt->warmupFrames);
        auto sourceOptions = [&](int frame, bool firstInSequence) {
            io::CaptureSource::Options so = session.captureOptions(frame);
            so.strict = opt->strict;
            so.firstInSequence = firstInSequence;
            return so;
        };
        auto verbosePass = [](int, int, const PassReport& p) {
            std::string work;
            for (const auto& [k, v] : p.work)
                work += fmt::format(" {}={}", k, v);
            logVerbose(fmt::format("  {:<24} {:>9.2f} ms{}", p.name, p.seconds * 1e3, work));
        };
        for (std::size_t i = 0; i < warmup.size(); ++i) {
            const io::CaptureSource::Options so = sourceOptions(warmup[i], i == 0);
            io::CaptureSource source(so, session.profile());
            logVerbose(fmt::format("warm-up frame {}:", warmup[i]));
            DiscardSink discard;
            const FrameReport fr = executePlan(plan, source, discard, verbosePass, &history);
            for (const auto& [role, path] : source.filesRead())
                addInput(role, path);
            std::cout << fmt::format("warm-up frame {}: {} passes in {:.3f} s\n", warmup[i],
                                     fr.passes.size(), fr.seconds);
        }
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const io::CaptureSource::Options so =
                sourceOptions(frames[i], i == 0 && warmup.empty());
            io::CaptureSource source(so, session.profile());
            FP_CHECK(!plan.needsCamera || source.frameInfo().hasCamera,
                     "{}: frame {}: no camera in the header and no sidecar ({}.camera.json)",
                     so.path, frames[i], so.path);
            const std::size_t before = writer.written().size();
            logVerbose(fmt::format("frame {}:", frames[i]));
            const FrameReport fr = executePlan(
                plan, source, writer,
                [&](int done, int total, const PassReport& pass) {
                    verbosePass(done, total, pass);
                    const double progress =
                        (double(i) + double(done) / std::max(total, 1)) / frames.size();
                    logProgress(int(progress * 100.0));
                },
                &history);
            for (const auto& [role, path] : source.filesRead())
                addInput(role, path);
            const auto& s = source.sanitized();
            if (s.total() > 0)
                logWarning(
                    fmt::format("{}: sanitized {} non-finite, {} negative colour "
                                "and {} non-unit normal values",
                                so.path, s.nonFinite, s.negative, s.nonUnitNormals));
            nlohmann::json fj = fr.toJson();
            fj["capture"] = so.path;
            fj["channelsRead"] = source.readLog();
            for (const auto& n : source.notes())
                if (notesShown.insert(n).second) logWarning(n);
            fj["written"] =
                std::vector<std::string>(writer.written().begin() + before, writer.written().end());
            report["frames"].push_back(fj);
            std::cout << fmt::format("frame {}: {} passes in {:.3f} s, peak {:.1f} MiB\n",
                                     frames[i], fr.passes.size(), fr.seconds,
                                     fr.peakBytes / 1048576.0);
            for (const auto& p : fr.passes) {
                std::string work;
                for (const auto& [k, v] : p.work)
                    work += fmt::format(" {}={}", k, v);
                std::cout << fmt::format("  {:<24} {:>9.2f} ms{}\n", p.name, p.seconds * 1e3, work);
                if (!p.metrics.empty()) {
                    std::string m;
                    for (const auto& [k, v] : p.metrics)
                        m += fmt::format(" {}={:.5g}", k, v);
                    std::cout << fmt::format("  {:<24} {}\n", "", m);
                }
            }
            for (std::size_t w = before; w < writer.written().size(); ++w)
                std::cout << "  wrote " << writer.written()[w] << "\n";
        }
        if (!opt->report.empty()) {
            for (const auto& [role, path] : session.inputs().filesRead())
                addInput(role, path);
            report["inputs"] = inputs;
            report["plan"] = plan.toJson(session.extent());
            const auto parent = std::filesystem::path(opt->report).parent_path();
            if (!parent.empty())
                std::filesystem::create_directories(parent);
            std::ofstream(opt->report) << report.dump(2) << "\n";
            std::cout << "  wrote " << opt->report << "\n";
        }
        return 0;
    };
}

}  // namespace fp::cli
