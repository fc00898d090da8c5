#include "app/RunFrames.h"

#include "app/BenchResult.h"
#include "app/ErrorBreakdown.h"
#include "app/FrameDriver.h"
#include "app/Invocation.h"
#include "app/MemoryLimit.h"
#include "io/CaptureSource.h"
#include "io/FramePattern.h"
#include "io/OutputLock.h"
#include "io/OutputQueue.h"
#include "io/OutputWriter.h"
#include "io/TevClient.h"
#include "io/SafeFiles.h"
#include "foundation/Error.h"
#include "framework/Executor.h"

#include <fmt/chrono.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <array>
#include <chrono>
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>

namespace fp::app {

namespace {
// Warm-up frames produce history only.
class DiscardSink final : public FrameSink {
public:
    void write(const OutputDesc&, const std::vector<OutputLayer>&, const FrameInfo&) override {}
};

// --decompose-rays: keeps the images of the error sources a decomposition reads, and hands
// every output on to `inner` except the dumps planned only to reach those sources.
class DecompositionSink final : public FrameSink {
public:
    DecompositionSink(FrameSink& inner, const std::set<std::string>& sources,
                      const std::set<std::string>& extraDumps)
        : mInner(inner), mSources(sources), mExtraDumps(extraDumps) {}
    void write(const OutputDesc& output, const std::vector<OutputLayer>& layers,
               const FrameInfo& frame) override {
        for (const auto& l : layers)
            if (mSources.count(l.name))
                images[l.name] = l.texture->image();
        if (!(output.isDump && output.sources.size() == 1 &&
              mExtraDumps.count(output.sources.front())))
            mInner.write(output, layers, frame);
    }
    std::map<std::string, Image> images;

private:
    FrameSink& mInner;
    const std::set<std::string>& mSources;
    const std::set<std::string>& mExtraDumps;
};

// The frame's error_measure results, as bench has them, for the decomposition.
std::vector<ErrorNodeResult> frameErrors(const Plan& plan, const FrameReport& fr) {
    std::vector<ErrorNodeResult> errors;
    for (std::size_t s = 0; s < plan.steps.size() && s < fr.passes.size(); ++s)
        if (plan.steps[s].io.roles.measuresError)
            errors.push_back(errorNodeResult(plan.steps[s], fr.passes[s]));
    return errors;
}

// The `count` frames before the first, spaced like the sequence (its first step, else 1), that
// have a capture on disk (a sequence's start cuts the warm-up short).
std::vector<int> warmupFrames(const RunSetup& session, int count) {
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

// The console lines of one finished frame: its passes' times, work and metrics, its files.
void printFrame(std::ostream& out, const FrameReport& fr, const std::vector<std::string>& written) {
    out << fmt::format("frame {}: {} passes in {:.3f} s, peak {:.1f} MiB\n", fr.frame,
                             fr.passes.size(), fr.seconds, fr.peakBytes / 1048576.0);
    for (const auto& p : fr.passes) {
        std::string work;
        for (const auto& [k, v] : p.work)
            work += fmt::format(" {}={}", k, v);
        out << fmt::format("  {:<24} {:>9.2f} ms{}\n", p.name, p.seconds * 1e3, work);
        if (!p.metrics.empty()) {
            std::string m;
            for (const auto& [k, v] : p.metrics)
                m += fmt::format(" {}={:.5g}", k, v);
            out << fmt::format("  {:<24} {}\n", "", m);
        }
    }
    for (const auto& w : written)
        out << "  wrote " << w << "\n";
}

// Where one frame's time went, stage by stage (the report's per-frame figures).
struct FrameStages {
    enum Stage { Read, Decode, Upload, Pass, Download, Encode, Write, kStages };
    static constexpr std::array<const char*, kStages> kNames = {
        "read", "decode", "upload", "pass", "download", "encode", "write"};
    std::array<double, kStages> seconds{};

    static FrameStages of(const FrameReport& r, const FrameSource::InputSeconds& input,
                          const io::OutputQueue::FrameFiles& files) {
        FrameStages s;
        s.seconds = {input.read,         input.decode,        r.uploadSeconds, 0.0,
                     r.downloadSeconds, files.encodeSeconds, files.writeSeconds};
        for (const auto& p : r.passes) s.seconds[Pass] += p.seconds;
        return s;
    }
    /// As the report names them: "readSeconds", …
    void addTo(nlohmann::json& j) const {
        for (int i = 0; i < kStages; ++i) j[std::string(kNames[i]) + "Seconds"] = seconds[i];
    }
};

// The stages summed over a run's frames, and what bounds its frame rate. Reading runs on the
// read-ahead threads beside the frames' computing, and the files on the writers beside both: the
// slowest of the three (reading's share divided among the frames read at once, the writers'
// among them) sets the pace. Without read-ahead and writers every stage takes its turn on one
// thread, and the largest bounds the rate.
struct StageTotals {
    FrameStages sum;
    int frames = 0;
    void add(const FrameStages& s) {
        for (int i = 0; i < FrameStages::kStages; ++i) sum.seconds[i] += s.seconds[i];
        ++frames;
    }
    FrameStages perFrame() const {
        FrameStages mean = sum;
        for (double& v : mean.seconds) v /= std::max(frames, 1);
        return mean;
    }
    std::string bound(int readAhead, int writers) const {
        using S = FrameStages;
        const auto s = perFrame().seconds;
        auto largest = [&](std::initializer_list<S::Stage> of) {
            S::Stage best = *of.begin();
            for (S::Stage i : of)
                if (s[i] > s[best]) best = i;
            return std::string(S::kNames[best]);
        };
        if (readAhead == 0 && writers == 0)
            return largest({S::Read, S::Decode, S::Upload, S::Pass, S::Download, S::Encode, S::Write});
        const double reading = s[S::Read] + s[S::Decode];
        const double writing = s[S::Encode] + s[S::Write];
        const double input = readAhead > 0 ? reading / readAhead : 0;
        const double compute = s[S::Upload] + s[S::Pass] + s[S::Download] +
                               (readAhead > 0 ? 0.0 : reading) + (writers == 0 ? writing : 0.0);
        const double output = writers > 0 ? writing / writers : 0;
        if (readAhead > 0 && input >= compute && input >= output) return largest({S::Read, S::Decode});
        if (output >= compute) return largest({S::Encode, S::Write});
        return largest({S::Upload, S::Pass, S::Download});
    }
    nlohmann::json toJson(double wall, int readAhead, int writers) const {
        nlohmann::json perStage;
        perFrame().addTo(perStage);
        return {{"frames", frames},
                {"seconds", wall},
                {"framesPerSecond", frames / std::max(wall, 1e-9)},
                {"boundBy", bound(readAhead, writers)},
                {"perFrame", perStage},
                {"readAhead", readAhead},
                {"writers", writers}};
    }
    std::string line(double wall, int readAhead, int writers) const {
        const FrameStages mean = perFrame();
        std::string stages;
        for (int i = 0; i < FrameStages::kStages; ++i)
            stages += fmt::format("{}{} {:.3f}", i ? ", " : "", FrameStages::kNames[i],
                                  mean.seconds[i]);
        return fmt::format("{} frame{} in {:.2f} s: {:.2f} frames/s, bound by {}; seconds a "
                           "frame: {}",
                           frames, frames == 1 ? "" : "s", wall, frames / std::max(wall, 1e-9),
                           bound(readAhead, writers), stages);
    }
};

// What a stored exception says.
std::string messageOf(const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const std::exception& e) {
        return e.what();
    } catch (...) {
        return "an error that is no std::exception";
    }
}

bool hasTemporalPass(const Plan& plan) {
    return std::any_of(plan.steps.begin(), plan.steps.end(),
                       [](const PlanStep& s) { return s.io.temporal; });
}

}  // namespace

int defaultReadAhead(int threads) { return std::clamp(threads / 4, 1, 4); }
int defaultWriters(int threads) { return std::clamp(threads / 4, 2, 8); }

RunOutcome runFrames(const RunOptions& given, std::ostream& out, std::ostream& err) {
    RunOptions opt = given;
    if (opt.readAhead < 0) opt.readAhead = defaultReadAhead(invocation().threads);
    if (opt.writers < 0) opt.writers = defaultWriters(invocation().threads);
    // With --decompose-rays the chain is planned again with the error sources as dumps
    // that DecompositionSink keeps in memory instead of writing.
    const RunSetup planned(opt.setup);
    std::vector<DecompositionTarget> targets;
    std::set<std::string> sources, extraDumps;
    SetupOptions sessionOptions = opt.setup;
    if (opt.decomposeRays > 0) {
        const auto capture = planned.openCapture(planned.capturePath(planned.frames().front()));
        targets = decompositionTargets(
            planned.plan(), capture ? capture->availableBuffers() : std::set<std::string>{});
        if (targets.empty())
            logWarning("--decompose-rays: no error_measure of this chain measures a "
                       "screen-space pass against a diffuse-indirect or AO truth of the "
                       "capture: nothing to take apart");
        for (const auto& t : targets) {
            sources.insert(t.source);
            if (std::find(sessionOptions.dumps.begin(), sessionOptions.dumps.end(),
                          t.source) == sessionOptions.dumps.end() &&
                extraDumps.insert(t.source).second)
                sessionOptions.dumps.push_back(t.source);
        }
    }
    std::optional<RunSetup> replanned;
    if (!extraDumps.empty())
        replanned.emplace(planned, sessionOptions);
    const RunSetup& session = replanned ? *replanned : planned;
    const Plan& plan = session.plan();
    for (const auto& w : plan.warnings)
        logWarning(fmt::format("{}: {}", w.pointer, w.message));
    const auto& frames = session.frames();

    // A file name without a frame token would hold only the last of several frames (and two
    // chunks of a farm run would write the same file): refused before the first frame.
    if (frames.size() > 1)
        for (const auto& o : plan.outputs)
            if (!o.isDump && !io::FramePattern(o.file).hasFrameToken()) {
                const std::filesystem::path name(o.file);
                throw UsageError(fmt::format(
                    "output \"{}\" has no frame token (#### or %04d) but this run writes {} "
                    "frames, so each frame would overwrite the last; name it \"{}\" (or run one "
                    "frame with --frames)",
                    o.file, frames.size(),
                    (name.parent_path() / (name.stem().string() + ".####" +
                                           name.extension().string()))
                        .string()));
            }

    // Nothing this run writes may be one of its inputs.
    std::vector<std::string> inputs = {opt.setup.config, session.config().scene};
    for (int f : frames) {
        inputs.push_back(session.capturePath(f));
        inputs.push_back(session.cameraPath(f));
    }
    // "--report -": the report is the only thing on stdout; the frame lines go to stderr.
    const bool reportToStdout = opt.report == "-";
    std::ostream& console = reportToStdout ? err : out;
    if (!opt.report.empty() && !reportToStdout) {
        io::refuseToOverwriteInputs(opt.report, inputs, "--report");
        io::checkWritable(opt.report, "--report");
    }
    io::OutputWriter::Options wo;
    wo.outputDir = opt.outputDir;
    wo.compression = io::parseCompression(session.config().compression);
    wo.halfColor = session.config().colorPrecision == "half";
    wo.pngLevel = session.config().pngLevel;
    wo.protectedPaths.insert(inputs.begin(), inputs.end());
    wo.protectedPaths.erase("");
    io::checkFolderWritable(opt.outputDir, "-o");
    // The process's peak, forecast before a pixel is read (app/MemoryLimit.h), checked against
    // --max-memory and reported beside the peak reached.
    std::optional<MemoryForecast> forecast;
    if (session.extent().width > 0) {
        forecast = forecastMemory(plan, session.extent(), int(frames.size()) + opt.warmupFrames,
                                  opt.readAhead, wo.halfColor, opt.writers);
        checkMemory(forecast->total(), describeForecast(*forecast), opt.maxMemory,
                    int(opt.setup.dumps.size()));
    }
    const io::OutputLock lock(opt.outputDir, frames);
    io::OutputWriter writer(wo);
    io::OutputQueue queue(writer, opt.writers);
    // --tev: every output also goes to the viewer (connected now: a wrong address fails first).
    std::optional<io::TevClient> tev;
    std::optional<io::TevSink> tevSink;
    if (!opt.tev.empty()) {
        tev.emplace(opt.tev);
        tevSink.emplace(queue, *tev);
    }
    FrameSink& outputs = tevSink ? static_cast<FrameSink&>(*tevSink) : queue;
    // What a killed run left half-written: its temporaries (the final names are always whole).
    int stale = 0;
    for (const auto& dir : {opt.outputDir, writer.dumpDir()})
        stale += io::removeStaleTemporaries(dir);
    if (!opt.report.empty() && !reportToStdout)
        stale += io::removeStaleTemporaries(
            std::filesystem::path(opt.report).parent_path().empty()
                ? "."
                : std::filesystem::path(opt.report).parent_path().string());
    if (stale > 0)
        logInfo(fmt::format("removed {} temporary file(s) a killed run left", stale));

    const Invocation& inv = invocation();
    nlohmann::json report = {
        {"framepass", {{"version", inv.version}}},
        {"commandLine", inv.commandLine()},
        {"arguments", inv.arguments},
        {"threads", {{"requested", inv.threadsRequested}, {"used", inv.threads}}},
        {"config", opt.setup.config},
        {"frames", nlohmann::json::array()}};
    // Every file read, once, in the order first read.
    nlohmann::json inputFiles = nlohmann::json::array();
    std::set<std::string> listed;
    auto addInput = [&](const std::string& role, const std::string& path) {
        if (!path.empty() && listed.insert(role + "\n" + path).second)
            inputFiles.push_back(inputFile(role, path));
    };
    addInput("config", opt.setup.config);
    addInput("preset", session.config().preset);
    auto writeReport = [&]() {
        if (opt.report.empty())
            return;
        for (const auto& [role, path] : session.inputs().filesRead())
            addInput(role, path);
        report["inputs"] = inputFiles;
        report["plan"] = plan.toJson(session.extent());
        if (forecast) {
            // The forecast the run was admitted on, beside the peak the process reached.
            report["memory"] = {{"forecast", forecast->toJson()},
                                {"peakResidentBytes", peakResidentBytes()}};
        }
        if (reportToStdout) {
            out << report.dump(2) << "\n";
        } else {
            io::writeFileAtomically(opt.report, report.dump(2) + "\n");
            console << "  wrote " << opt.report << "\n";
        }
    };

    std::set<std::string> notesShown;  // each assumption once, not once per frame
    auto verbosePass = [](int, int, const PassReport& p) {
        throwIfStopped();  // between passes: the safe point
        std::string work;
        for (const auto& [k, v] : p.work)
            work += fmt::format(" {}={}", k, v);
        logVerbose(fmt::format("  {:<24} {:>9.2f} ms{}", p.name, p.seconds * 1e3, work));
    };
    // The frames run through one driver: the next frames' captures read while one runs (unless
    // --read-ahead 0), the history carried from frame to frame.
    FrameDriver driver(session, {.keep = CaptureKeeping::Streaming,
                                 .readAhead = opt.readAhead,
                                 .strict = opt.setup.strict});
    // One frame into `sink`: its notes said, its files recorded; `next` is read while it runs.
    auto runFrame = [&](int frame, FrameSink& sink, const ProgressFn& progress,
                        const std::vector<int>& next) {
        FrameRun run = driver.run(plan, frame, sink, progress, next);
#if defined(__GLIBC__)
        // What the frame freed goes back to the system before the next one: glibc keeps freed
        // blocks in its arenas (and once the first frame's planes are freed its mmap threshold
        // rises, so later frames' planes come from those arenas), which raised a sequence's peak
        // 17–25 % above the forecast (docs/results/memory.md); the trim costs no measurable time.
        malloc_trim(0);
#endif
        nlohmann::json fj = run.report.toJson();
        fj["capture"] = session.capturePath(frame);
        if (io::CaptureSource* source = run.capture) {
            for (const auto& [role, path] : source->filesRead())
                addInput(role, path);
            const auto& s = source->sanitized();
            if (s.total() > 0)
                logWarning(fmt::format("{}: sanitized {} non-finite, {} negative colour and {} "
                                       "non-unit normal values",
                                       session.capturePath(frame), s.nonFinite, s.negative,
                                       s.nonUnitNormals));
            for (const auto& n : source->notes())
                if (notesShown.insert(n).second) logWarning(n);
            for (const auto& w : source->files().warnings())
                if (notesShown.insert(w).second) logWarning(w);
            fj["channelsRead"] = source->readLog();
        }
        return std::make_pair(std::move(run), std::move(fj));
    };

    // Warm-up: the frames before the first, at the sequence's step, that exist on disk.
    const std::vector<int> warmup = warmupFrames(session, opt.warmupFrames);
    std::vector<int> sequence = warmup;
    sequence.insert(sequence.end(), frames.begin(), frames.end());
    driver.setSequence(sequence);
    for (std::size_t i = 0; i < warmup.size(); ++i) {
        try {
            throwIfStopped();
            logVerbose(fmt::format("warm-up frame {}:", warmup[i]));
            DiscardSink discard;
            const auto [run, fj] = runFrame(warmup[i], discard, verbosePass, {});
            console << fmt::format("warm-up frame {}: {} passes in {:.3f} s\n", warmup[i],
                                     run.report.passes.size(), run.report.seconds);
        } catch (const Interrupted& e) {
            report["interrupted"] = {{"warmupFrame", warmup[i]}, {"signal", e.signal()}};
            writeReport();
            throw;
        }
    }

    // --skip-existing: frames whose every output is on disk. With temporal passes, those
    // before a frame that is computed still run (writing nothing) so its history is the one
    // a sequential run gives it.
    std::vector<bool> skip(frames.size(), false);
    if (opt.skipExisting)
        for (std::size_t i = 0; i < frames.size(); ++i) {
            bool all = !plan.outputs.empty();
            for (const auto& o : plan.outputs)
                all = all && std::filesystem::exists(writer.pathFor(o, frames[i]));
            skip[i] = all;
        }
    const auto lastComputed = std::find(skip.rbegin(), skip.rend(), false);
    const std::size_t computeUntil =
        lastComputed == skip.rend() ? 0 : std::size_t(skip.rend() - lastComputed);
    const bool temporal = hasTemporalPass(plan);

    // The frames after frames[i] that run, as many as are read ahead.
    auto nextComputed = [&](std::size_t i) {
        std::vector<int> next;
        for (std::size_t k = i + 1; k < frames.size() && int(next.size()) < opt.readAhead; ++k)
            if (!skip[k] || (temporal && k < computeUntil))
                next.push_back(frames[k]);
        return next;
    };

    // The pipeline: a frame's files are written by the queue's writers while the next frame
    // computes. A frame is settled — its files waited for, its lines printed, its report entry
    // made — once the frame after it has computed (or at the end), so at most two frames' outputs
    // are held at once.
    struct Computed {
        int frame = 0;
        bool forHistoryOnly = false;
        FrameReport report;
        FrameSource::InputSeconds input;
        nlohmann::json entry;
        std::vector<ErrorNodeResult> errors;
    };
    std::optional<Computed> inFlight;
    std::vector<int> failed;
    StageTotals totals;
    // Settles `c`: returns the error of a file that failed to write (the frame then failed).
    auto settle = [&](Computed& c) -> std::exception_ptr {
        const io::OutputQueue::FrameFiles files = queue.finish(c.frame);
        c.entry["written"] = files.written;
        const FrameStages stages = FrameStages::of(c.report, c.input, files);
        stages.addTo(c.entry);
        if (files.error) {
            report["frames"].push_back({{"frame", c.frame},
                                        {"status", "failed"},
                                        {"error", messageOf(files.error)},
                                        {"written", files.written}});
            return files.error;
        }
        report["frames"].push_back(c.entry);
        if (c.forHistoryOnly) {
            logInfo(fmt::format("frame {}: every output exists, run for history only", c.frame));
            return nullptr;
        }
        totals.add(stages);
        printFrame(console, c.report, files.written);
        for (const auto& e : c.errors)
            if (e.decomposition)
                console << fmt::format("  {} ({} against {}):\n", e.name, e.source, e.reference)
                        << decompositionText(*e.decomposition);
        return nullptr;
    };
    // The run ends with `error` (a frame that failed, without --continue-on-error): the report
    // is written first.
    auto endRun = [&](std::exception_ptr error) {
        try {
            writeReport();
        } catch (const Error& reportError) {
            // Both are said: the frame's error is the one that ends the run.
            err << "framepass error: " << reportError.what() << "\n";
        }
        std::rethrow_exception(error);
    };
    // Settles the frame in flight; returns the error that ends the run (a file of it failed to
    // write, without --continue-on-error), else null.
    auto settleInFlight = [&]() -> std::exception_ptr {
        if (!inFlight) return nullptr;
        Computed c = std::move(*inFlight);
        inFlight.reset();
        const std::exception_ptr error = settle(c);
        if (!error || !opt.continueOnError) return error;
        err << fmt::format("framepass error: frame {}: {}\n", c.frame, messageOf(error));
        failed.push_back(c.frame);
        return nullptr;
    };
    const auto started = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < frames.size(); ++i) {
        nlohmann::json status = {{"frame", frames[i]}};
        if (skip[i] && !(temporal && i < computeUntil)) {
            if (const auto error = settleInFlight()) endRun(error);
            status["status"] = "skipped";
            report["frames"].push_back(status);
            driver.cut();
            logInfo(fmt::format("frame {}: every output exists, skipped", frames[i]));
            continue;
        }
        Computed c;
        c.frame = frames[i];
        c.forHistoryOnly = skip[i];
        try {
            throwIfStopped();
            logVerbose(fmt::format("frame {}:", frames[i]));
            DiscardSink discard;
            DecompositionSink kept(skip[i] ? static_cast<FrameSink&>(discard) : outputs,
                                   sources, extraDumps);
            const ProgressFn frameProgress = [&](int done, int total,
                                                 const PassReport& pass) {
                verbosePass(done, total, pass);
                const double progress =
                    (double(i) + double(done) / std::max(total, 1)) / frames.size();
                logProgress(int(progress * 100.0));
            };
            auto [run, fj] = runFrame(frames[i], kept, frameProgress, nextComputed(i));
            c.report = std::move(run.report);
            c.input = run.input;
            c.entry = std::move(fj);
            c.entry["status"] = skip[i] ? "skipped (run for the history of later frames)" : "ok";
            // The frame's screen-space errors taken apart: the oracle and the converged
            // chain on this frame's capture, the result as this run made it (with history).
            if (!targets.empty() && !skip[i]) {
                ErrorBreakdown decomposer(session, driver, targets, opt.decomposeRays, frames[i]);
                c.errors = frameErrors(plan, c.report);
                decomposer.decompose(opt.setup, kept.images,
                                     fmt::format("frame {}", frames[i]), c.errors);
                for (const auto& e : c.errors)
                    if (e.decomposition)
                        c.entry["errorDecomposition"][e.name] = e.decomposition->toJson();
            }
        } catch (const Interrupted& e) {
            // Stopped between passes: the frame before is settled (its files finished whole),
            // nothing is half-written (outputs go through temporaries renamed into place), and
            // the report says where the run stopped.
            (void)settleInFlight();
            queue.finish(frames[i]);
            status["status"] = "interrupted";
            status["error"] = e.what();
            report["frames"].push_back(status);
            report["interrupted"] = {{"frame", frames[i]}, {"signal", e.signal()}};
            writeReport();
            throw;
        } catch (const Error& e) {
            const std::exception_ptr before = settleInFlight();
            queue.finish(frames[i]);  // what it handed over before failing, finished
            status["status"] = "failed";
            status["error"] = e.what();
            report["frames"].push_back(status);
            if (before) endRun(before);
            if (!opt.continueOnError) endRun(std::current_exception());
            err << fmt::format("framepass error: frame {}: {}\n", frames[i], e.what());
            failed.push_back(frames[i]);
            driver.cut();  // the next frame has no history: as after a camera cut
            continue;
        }
        // Frame N computed: frame N−1's files are waited for now (they were written while N
        // computed), and N's go on being written while N+1 computes.
        if (const auto error = settleInFlight()) {
            (void)settle(c);  // its files finish whole; the report lists them
            endRun(error);
        }
        inFlight = std::move(c);
    }
    if (const auto error = settleInFlight()) endRun(error);
    report["failedFrames"] = failed;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (totals.frames > 0) {
        report["throughput"] = totals.toJson(wall, opt.readAhead, queue.writers());
        console << totals.line(wall, opt.readAhead, queue.writers()) << "\n";
    }
    if (forecast) {
        const uint64_t peak = peakResidentBytes();
        console << fmt::format("memory: the process peaked at {}, forecast {} ({:+.0f} %)\n",
                               formatBytes(peak), formatBytes(forecast->total()),
                               100.0 * (double(peak) / double(forecast->total()) - 1.0));
    }
    writeReport();
    return {std::move(report), std::move(failed), int(frames.size())};
}

}  // namespace fp::app
