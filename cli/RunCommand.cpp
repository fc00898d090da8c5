// framepass run: execute the chain over the frames and write outputs, dumps and a report.
#include "cli/Commands.h"
#include "cli/RunSession.h"
#include "io/CaptureSource.h"
#include "io/OutputWriter.h"
#include "passes/core/Error.h"
#include "passes/core/Executor.h"

#include <filesystem>
#include <set>
#include <fstream>
#include <iostream>

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
            std::cerr << fmt::format("warning: {}: {}\n", w.pointer, w.message);

        io::OutputWriter::Options wo;
        wo.outputDir = opt->outputDir;
        wo.compression = io::parseCompression(session.config().compression);
        wo.protectedPaths.insert(opt->session.config);
        for (int f : session.frames())
            wo.protectedPaths.insert(session.capturePath(f));
        io::OutputWriter writer(wo);

        nlohmann::json report = {{"config", opt->session.config},
                                 {"frames", nlohmann::json::array()}};
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
        for (std::size_t i = 0; i < warmup.size(); ++i) {
            io::CaptureSource source(sourceOptions(warmup[i], i == 0), session.profile());
            DiscardSink discard;
            const FrameReport fr = executePlan(plan, source, discard, {}, &history);
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
            const FrameReport fr = executePlan(
                plan, source, writer,
                [&](int done, int total) {
                    const double progress =
                        (double(i) + double(done) / std::max(total, 1)) / frames.size();
                    std::cout << fmt::format("Progress: {}%\n", int(progress * 100.0))
                              << std::flush;
                },
                &history);
            const auto& s = source.sanitized();
            if (s.total() > 0)
                std::cerr << fmt::format(
                    "warning: {}: sanitized {} non-finite, {} negative colour "
                    "and {} non-unit normal values\n",
                    so.path, s.nonFinite, s.negative, s.nonUnitNormals);
            nlohmann::json fj = fr.toJson();
            fj["capture"] = so.path;
            fj["channelsRead"] = source.readLog();
            for (const auto& n : source.notes())
                if (notesShown.insert(n).second) std::cerr << "warning: " << n << "\n";
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
