// framepass bench: runs a chain several times on one frame and reports each pass's median time
// and throughput; --sweep varies cvars or parameters over a grid and, where the chain measures
// error against truth (error_measure passes), produces the speed-against-error table, its Pareto
// front, and an HTML report.
#include "cli/BareRayLoop.h"
#include "cli/BenchResult.h"
#include "cli/Commands.h"
#include "cli/Invocation.h"
#include "cli/RunSession.h"
#include "io/CaptureSource.h"
#include "io/ContactSheet.h"
#include "io/PngWriter.h"
#include "passes/core/Error.h"
#include "passes/core/Executor.h"
#include "passes/display/DisplayTransform.h"
#include "passes/metrics/Heatmap.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include <tbb/global_control.h>

namespace fp::cli {

namespace {

constexpr const char* kErrorPassType = "error_measure";
constexpr const char* kShadowPassType = "rt_shadows";
// Not a pass: the Embree yardstick listed with the passes (BareRayLoop.h).
constexpr const char* kBareLoopType = "embree";

/// A frame source that reads each buffer from the capture once and serves copies afterwards,
/// so repeated runs time the passes, not the disk.
class CachedSource final : public FrameSource {
public:
    explicit CachedSource(FrameSource& inner) : mInner(inner) {}
    FrameInfo frameInfo() override { return mInner.frameInfo(); }
    Texture loadBuffer(const std::string& buffer, int channels) override {
        auto it = mCache.find(buffer);
        if (it == mCache.end())
            it = mCache.emplace(buffer, mInner.loadBuffer(buffer, channels)).first;
        return it->second;
    }
    const RayScene& scene() override { return mInner.scene(); }
    const std::vector<Light>& lights() override { return mInner.lights(); }
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() override { return mInner.colorConfig(); }
    const Texture* cached(const std::string& buffer) const {
        auto it = mCache.find(buffer);
        return it == mCache.end() ? nullptr : &it->second;
    }

private:
    FrameSource& mInner;
    std::map<std::string, Texture> mCache;
};

/// Discards outputs, except on the run that keeps the images for the report.
class KeepingSink final : public FrameSink {
public:
    bool keep = false;
    std::map<std::string, Image> images;
    void write(const OutputDesc&,
               const std::vector<OutputLayer>& layers,
               const FrameInfo&) override {
        if (!keep)
            return;
        for (const auto& l : layers)
            images[l.name] = l.texture->image();
    }
};

struct SweepAxis {
    std::string name;
    std::vector<std::string> values;
};

// "NAME=V1,V2,..." or "NAME=A..B" (integers).
SweepAxis parseSweep(const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
        throw UsageError(fmt::format("--sweep {}: expected NAME=V1,V2,... or NAME=A..B", text));
    SweepAxis axis{text.substr(0, eq), {}};
    const std::string list = text.substr(eq + 1);
    if (const auto dots = list.find(".."); dots != std::string::npos) {
        try {
            std::size_t endA = 0, endB = 0;
            const int a = std::stoi(list.substr(0, dots), &endA);
            const int b = std::stoi(list.substr(dots + 2), &endB);
            if (endA != dots || endB != list.size() - dots - 2 || b < a)
                throw std::invalid_argument("");
            for (int v = a; v <= b; ++v)
                axis.values.push_back(std::to_string(v));
        } catch (const std::exception&) {
            throw UsageError(
                fmt::format("--sweep {}: a range is two integers A..B with A ≤ B", text));
        }
        return axis;
    }
    std::size_t start = 0;
    while (start <= list.size()) {
        const auto comma = list.find(',', start);
        const std::string v =
            list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (v.empty())
            throw UsageError(fmt::format("--sweep {}: empty value", text));
        axis.values.push_back(v);
        if (comma == std::string::npos)
            break;
        start = comma + 1;
    }
    return axis;
}

std::string base64(const std::string& bytes) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 |
                           (unsigned char)bytes[i + 2];
        out += {k[v >> 18 & 63], k[v >> 12 & 63], k[v >> 6 & 63], k[v & 63]};
    }
    if (i + 1 == bytes.size()) {
        const unsigned v = (unsigned char)bytes[i] << 16;
        out += {k[v >> 18 & 63], k[v >> 12 & 63], '=', '='};
    } else if (i + 2 == bytes.size()) {
        const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
        out += {k[v >> 18 & 63], k[v >> 12 & 63], k[v >> 6 & 63], '='};
    }
    return out;
}

using SweepPoint = std::vector<std::pair<std::string, std::string>>;

struct BenchOptions {
    SessionOptions session;
    int runs = 5, warmup = 1;
    std::vector<std::string> sweeps;
    bool json = false;
    std::string html;
};

// Every combination of the sweep values, first axis slowest.
std::vector<SweepPoint> sweepGrid(const std::vector<std::string>& sweeps) {
    std::vector<SweepPoint> grid = {{}};
    for (const auto& text : sweeps) {
        const SweepAxis axis = parseSweep(text);
        std::vector<SweepPoint> next;
        for (const auto& g : grid)
            for (const auto& v : axis.values) {
                auto e = g;
                e.emplace_back(axis.name, v);
                next.push_back(e);
            }
        grid = next;
    }
    return grid;
}

// error_measure passes are roots here even when the config writes none of their outputs; the
// ports they compare are kept for the report's images.
std::vector<std::string> errorDumps(const GraphDesc& graph) {
    std::vector<std::string> dumps;
    for (const auto& n : graph.nodes) {
        if (n.type != kErrorPassType)
            continue;
        dumps.push_back(n.name + ".heat");
        for (const char* port : {"source", "reference"})
            if (auto it = n.inputs.find(port);
                it != n.inputs.end() && it->second.rfind("capture:", 0) != 0)
                dumps.push_back(it->second);
    }
    return dumps;
}

// The images of one error_measure for the HTML report: result, truth and heat map as PNG, the
// heat map with its colour bar from 0 to the pass's heat scale.
ErrorImages errorImages(const std::string& heat,
                        const ErrorNodeResult& e,
                        CachedSource& source,
                        const KeepingSink& sink,
                        SessionInputs& inputs) {
    const DisplayTransform display(inputs.colorConfig(), "scene_linear", "", "", 0.0f, true);
    auto find = [&](const std::string& key) -> const Image* {
        if (key.rfind("capture:", 0) == 0) {
            if (const Texture* t = source.cached(key.substr(8)))
                return &t->image();
        } else if (auto it = sink.images.find(key); it != sink.images.end()) {
            return &it->second;
        }
        return nullptr;
    };
    auto preview = [&](const std::string& key) -> std::string {
        const Image* img = find(key);
        return img ? base64(io::encodePng(display.apply(*img))) : std::string();
    };
    std::string heatPng;
    if (const Image* img = find(heat)) {
        const auto it = e.metrics.find("heatScale");
        const Image shown =
            it == e.metrics.end()
                ? display.apply(*img)
                : io::withColorBar(display.apply(*img), display.apply(heatmapRamp()), "0",
                                   fmt::format("{:.4g}", it->second), "|error|");
        heatPng = base64(io::encodePng(shown));
    }
    return {preview(e.source), preview(e.reference), heatPng};
}

// Replays the shadow rays of one more run through bare Embree loops (packets and single rays).
void addBareRayLoops(const Plan& plan,
                     CachedSource& source,
                     KeepingSink& sink,
                     const BenchOptions& opt,
                     BenchSetting& setting) {
    std::vector<Ray> rays;
    const RayScene& scene = source.scene();
    scene.setOcclusionLog(&rays);
    sink.keep = false;
    executePlan(plan, source, sink);
    scene.setOcclusionLog(nullptr);
    for (const bool packets : {true, false}) {
        std::vector<double> seconds;
        uint64_t blocked = 0;
        for (int r = 0; r < opt.warmup + opt.runs; ++r) {
            const double t = timeBareOcclusion(scene, rays, packets, blocked);
            if (r >= opt.warmup)
                seconds.push_back(t);
        }
        setting.passes.push_back({packets ? "bare loop rtcOccluded8" : "bare loop rtcOccluded1",
                                  kBareLoopType, "rays", rays.size(), TimingStats::of(seconds)});
    }
}

// Times one setting of the grid: warm-up runs, timed runs, then the per-pass table.
BenchSetting benchSetting(const RunSession& session,
                          const std::string& label,
                          const BenchOptions& opt,
                          BenchResult& result,
                          int& runsDone,
                          int totalRuns) {
    const Plan& plan = session.plan();
    const int frame = session.frames().front();
    const io::CaptureSource::Options co = session.captureOptions(frame);
    io::CaptureSource capture(co, session.profile());
    CachedSource source(capture);
    KeepingSink sink;
    result.capture = co.path;
    result.frame = frame;
    result.extent = session.extent();

    std::vector<std::vector<double>> stepSeconds(plan.steps.size()), stepGpuSeconds(plan.steps.size());
    std::vector<double> frameSeconds;
    FrameReport last;
    for (int r = 0; r < opt.warmup + opt.runs; ++r) {
        sink.keep = r + 1 == opt.warmup + opt.runs;
        last = executePlan(plan, source, sink);
        if (r >= opt.warmup) {
            frameSeconds.push_back(last.seconds);
            for (std::size_t s = 0; s < last.passes.size(); ++s) {
                stepSeconds[s].push_back(last.passes[s].seconds);
                if (last.passes[s].gpuSeconds)
                    stepGpuSeconds[s].push_back(*last.passes[s].gpuSeconds);
            }
        }
        logProgress(100 * ++runsDone / totalRuns);
    }

    BenchSetting setting;
    setting.label = label.empty() ? "default" : label;
    setting.frame = TimingStats::of(frameSeconds);
    setting.peakBytes = last.peakBytes;
    for (std::size_t s = 0; s < plan.steps.size(); ++s) {
        const PlanStep& step = plan.steps[s];
        PassTiming t{step.name, step.type, step.io.workUnit, 0, TimingStats::of(stepSeconds[s]), {}};
        if (!stepGpuSeconds[s].empty())
            t.gpuSeconds = TimingStats::of(stepGpuSeconds[s]);
        if (auto it = last.passes[s].work.find(t.unit); it != last.passes[s].work.end())
            t.work = it->second;
        setting.passes.push_back(t);
        if (step.type != kErrorPassType)
            continue;
        ErrorNodeResult e;
        e.name = step.name;
        e.metrics = last.passes[s].metrics;
        e.source = step.inputs.at("source").key;
        e.reference = step.inputs.at("reference").key;
        if (!opt.html.empty())
            e.images = errorImages(step.name + ".heat", e, source, sink, session.inputs());
        setting.errors.push_back(e);
    }
    if (std::any_of(plan.steps.begin(), plan.steps.end(),
                    [](const PlanStep& s) { return s.type == kShadowPassType; }))
        addBareRayLoops(plan, source, sink, opt, setting);
    return setting;
}

void printBench(const BenchResult& result) {
    std::cout << fmt::format(
        "{} on {} (frame {}, {}×{}): median of {} runs after {} warm-up, "
        "{} threads\n",
        result.config, result.capture, result.frame, result.extent.width, result.extent.height,
        result.runs, result.warmup, result.threads);
    for (const auto& s : result.settings) {
        std::cout << fmt::format("{}: frame {:.2f} ms (min {:.2f}, max {:.2f}), peak {:.1f} MiB "
                                 "({:.0f} B/pixel)",
                                 s.label, s.frame.median * 1e3, s.frame.min * 1e3,
                                 s.frame.max * 1e3, double(s.peakBytes) / 1048576.0,
                                 double(s.peakBytes) / (double(result.extent.width) * result.extent.height));
        if (s.hasError())
            std::cout << fmt::format(", RMSE {:.5g}{}", s.error(), s.pareto ? " [Pareto]" : "");
        std::cout << "\n";
        for (const auto& p : s.passes) {
            std::cout << fmt::format("  {:<24} {:>9.2f} ms  (min {:.2f}, max {:.2f})", p.name,
                                     p.seconds.median * 1e3, p.seconds.min * 1e3,
                                     p.seconds.max * 1e3);
            if (p.work)
                std::cout << fmt::format("  {:.2f} M{}/s", p.throughput() * 1e-6, p.unit);
            if (p.gpuSeconds)
                std::cout << fmt::format("  [gpu {:.3f} ms by CUDA events]",
                                         p.gpuSeconds->median * 1e3);
            std::cout << "\n";
        }
        for (const auto& e : s.errors) {
            std::string m;
            for (const auto& [k, v] : e.metrics)
                m += fmt::format(" {}={:.5g}", k, v);
            std::cout << fmt::format("  {} ({} against {}):{}\n", e.name, e.source, e.reference, m);
        }
    }
}

void writeHtml(const BenchResult& result, const std::string& path) {
    const auto parent = std::filesystem::path(path).parent_path();
    if (!parent.empty())
        std::filesystem::create_directories(parent);
    const std::string tmp = path + ".tmp";
    std::ofstream(tmp) << benchHtml(result);
    std::filesystem::rename(tmp, path);
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
    auto opt = std::make_shared<BenchOptions>();
    CLI::App* sub = app.add_subcommand(
        "bench",
        "time the chain over several runs (median, min, max, throughput per pass); "
        "--sweep gives the speed-against-error table");
    opt->session.addTo(*sub);
    sub->add_option("--runs", opt->runs, "timed runs per setting (default 5)")
        ->check(CLI::Range(1, 1000));
    sub->add_option("--warmup", opt->warmup, "untimed runs first (default 1)")
        ->check(CLI::Range(0, 100));
    sub->add_option("--sweep", opt->sweeps,
                    "vary a cvar or PASS.PARAM: NAME=V1,V2,... or NAME=A..B; several make a grid");
    sub->add_flag("--json", opt->json, "print the results as JSON");
    sub->add_option("--html", opt->html, "write a self-contained HTML report here");

    return [opt]() {
        const std::vector<SweepPoint> grid = sweepGrid(opt->sweeps);
        // The config and scene are read once; each sweep point is a new plan of the same chain.
        const RunSession probe(opt->session);
        for (const auto& w : probe.plan().warnings)
            logWarning(fmt::format("{}: {}", w.pointer, w.message));
        SessionOptions base = opt->session;
        for (const auto& d : errorDumps(probe.config().graph))
            base.dumps.push_back(d);

        BenchResult result;
        result.config = opt->session.config;
        result.runs = opt->runs;
        result.warmup = opt->warmup;
        result.sweeps = opt->sweeps;
        result.threads =
            int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
        const int totalRuns = int(grid.size()) * (opt->warmup + opt->runs);
        int runsDone = 0;
        for (const auto& point : grid) {
            SessionOptions so = base;
            std::string label;
            for (const auto& [name, value] : point) {
                (name.rfind("r.", 0) == 0 ? so.cvars : so.sets).push_back(name + "=" + value);
                label += (label.empty() ? "" : " ") + name + "=" + value;
            }
            const RunSession session(probe, so);
            result.settings.push_back(
                benchSetting(session, label, *opt, result, runsDone, totalRuns));
        }
        result.markPareto();

        if (opt->json)
            std::cout << result.toJson().dump(2) << "\n";
        else
            printBench(result);
        if (!opt->html.empty()) {
            writeHtml(result, opt->html);
            if (!opt->json)
                std::cout << "wrote " << opt->html << "\n";
        }
        return 0;
    };
}

}  // namespace fp::cli
