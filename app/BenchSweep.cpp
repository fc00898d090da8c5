#include "app/BenchSweep.h"

#include "app/BareRayLoop.h"
#include "app/BenchSources.h"
#include "app/Invocation.h"
#include "app/PlanReport.h"
#include "app/Session.h"
#include "io/ContactSheet.h"
#include "io/PngWriter.h"
#include "foundation/Error.h"
#include "framework/Executor.h"
#include "color/DisplayTransform.h"
#include "metrics/Heatmap.h"

#include <tbb/global_control.h>

#include <map>
#include <memory>

namespace fp::app {

namespace {

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

// Error measures are roots here even when the config writes none of their outputs; the ports
// they compare are kept for the report's images and the error decomposition. The config's
// "inputs" and then the settings' may rebind what they compare (--input ERROR.source=…): the
// rebound source is kept, and the one it replaced is not, so the method it fed is culled.
std::vector<std::string> errorDumps(const GraphDesc& graph, const Settings& settings) {
    std::map<std::string, std::string> rebound;  // "error.port" → source
    for (const auto& [target, value] : graph.inputs.items())
        if (value.is_string())
            rebound[target] = value.get<std::string>();
    for (const auto& [target, source] : settings.inputs)
        rebound[target] = source;
    std::vector<std::string> dumps;
    for (const NodeDesc* n : errorMeasureNodes(graph)) {
        dumps.push_back(n->name + ".heat");
        for (const char* port : {"source", "reference"}) {
            std::string source;
            if (auto r = rebound.find(n->name + "." + port); r != rebound.end())
                source = r->second;
            else if (auto it = n->inputs.find(port); it != n->inputs.end())
                source = it->second;
            if (!source.empty() && source.rfind("capture:", 0) != 0)
                dumps.push_back(source);
        }
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

// Replays the rays of one more run through bare Embree loops, each tracing pass's rays apart:
// occlusion rays in packets of 8 (the yardstick), of 16 where the pass traces them so (AVX-512),
// and single rays; where the chain reads a shadow pass's hit distance, also the pass's packets
// with their closest-hit queries (the same work); closest-hit rays one at a time. With more than
// one tracing pass each loop is named after its pass. Each pass that ran on the CPU gets its loops
// one ray at a time added up (PassTiming::bareSeconds): how near Embree's speed it traces.
void addBareRayLoops(const Plan& plan,
                     FrameDriver& frames,
                     int frame,
                     const BenchOptions& opt,
                     BenchSetting& setting) {
    RayScene::RayLog log;
    std::vector<std::pair<std::string, RayScene::RayLog>> perPass;
    const RayScene& scene = frames.source(frame).scene();
    scene.setRayLog(&log);
    KeepingSink sink;
    // After each pass, the rays it traced move to its own log (passes run one at a time).
    frames.cut();
    frames.run(plan, frame, sink, [&](int, int, const PassReport& pass) {
        if (log.rays.empty() && log.closestRays.empty())
            return;
        perPass.emplace_back(pass.name, std::move(log));
        log = RayScene::RayLog{};
    });
    scene.setRayLog(nullptr);
    auto timed = [&](const std::function<double()>& once) {
        std::vector<double> seconds;
        for (int r = 0; r < opt.warmup + opt.runs; ++r) {
            const double t = once();
            if (r >= opt.warmup)
                seconds.push_back(t);
        }
        return TimingStats::of(seconds);
    };
    for (const auto& traced : perPass) {
        const RayScene::RayLog& rays = traced.second;
        const std::string of = perPass.size() > 1 ? " (" + traced.first + ")" : "";
        struct Loop {
            int width;
            bool closestHits;
        };
        std::vector<Loop> loops;
        if (!rays.rays.empty()) {
            loops.push_back({8, false});
            if (scene.packetWidth() == 16)
                loops.push_back({16, false});
            loops.push_back({1, false});
            if (rays.closestHits)
                loops.push_back({scene.packetWidth(), true});
        }
        double oneAtATime = 0;  // its bare loops one ray at a time, added up: its yardstick
        for (const Loop& loop : loops) {
            uint64_t blocked = 0;
            setting.passes.push_back(
                {fmt::format("bare loop rtcOccluded{}{}{}", loop.width,
                             loop.closestHits ? fmt::format(" + rtcIntersect{}", loop.width) : "",
                             of),
                 kBareLoopType, "rays", rays.rays.size(), timed([&] {
                     return timeBareOcclusion(scene, rays.rays, loop.width, loop.closestHits,
                                              blocked);
                 })});
            if (loop.width == 1) oneAtATime += setting.passes.back().seconds.median;
        }
        // The closest-hit queries of the ray-traced GI, reflections and the hybrid.
        if (!rays.closestRays.empty()) {
            for (const int width : {scene.packetWidth(), 1}) {
                uint64_t hits = 0;
                setting.passes.push_back(
                    {fmt::format("bare loop rtcIntersect{}{}", width, of), kBareLoopType, "rays",
                     rays.closestRays.size(), timed([&] {
                         return timeBareClosestHit(scene, rays.closestRays, width, hits);
                     })});
                if (width == 1) oneAtATime += setting.passes.back().seconds.median;
            }
        }
        // Every ray of the pass, its shadow rays too, as a closest-hit query one at a time: the
        // yardstick of a pass that mixes the two kinds (docs/commands.md, bench).
        if (!rays.closestRays.empty() && !rays.rays.empty()) {
            std::vector<Ray> every = rays.closestRays;
            every.insert(every.end(), rays.rays.begin(), rays.rays.end());
            uint64_t hits = 0;
            setting.passes.push_back(
                {"bare loop rtcIntersect1, every ray" + of, kBareLoopType, "rays", every.size(),
                 timed([&] { return timeBareClosestHit(scene, every, 1, hits); })});
        }
        // Set on the pass when it ran on the CPU (a GPU pass's kernel is not Embree's match).
        for (PassTiming& p : setting.passes)
            if (p.name == traced.first && p.type != kBareLoopType && !p.gpuSeconds)
                p.bareSeconds = oneAtATime;
    }
}

}  // namespace

// Warm-up runs, timed runs, then the per-pass table and the errors (taken apart if asked).

BenchSetting Bencher::measure(const SweepPoint& point, bool decompose) {
    SetupOptions sessionOptions = mBase;
    for (const auto& [name, value] : point)
        applySetting(sessionOptions.settings, kindOf(name), name, value);
    for (const auto& d : errorDumps(mProbe.config().graph, sessionOptions.settings))
        sessionOptions.dumps.push_back(d);
    const RunSetup session(mProbe, sessionOptions);
    // A setting's own warnings (a swept cvar that the config's params shadow), each said once.
    for (const auto& w : session.plan().warnings)
        if (mWarned.insert(w.pointer + ": " + w.message).second)
            logWarning(w.pointer + ": " + w.message);
    // The error_measure passes live in the settings' plans (the probe's writes nothing).
    if (!mDecomposerChecked && mOptions.decomposeRays > 0) {
        mDecomposerChecked = true;
        // The error is the last frame's: its capture holds the rungs' truths.
        const int measured = mProbe.frames().back();
        const auto capture = mProbe.openCapture(mProbe.capturePath(measured));
        mMeasuredBuffers = capture ? capture->availableBuffers() : std::set<std::string>{};
        auto targets = decompositionTargets(session.plan(), mMeasuredBuffers);
        if (!targets.empty())
            mDecomposer.emplace(mProbe, mFrames, std::move(targets), mOptions.decomposeRays,
                                measured);
    }
    const BenchOptions& opt = mOptions;
    ErrorBreakdown* decomposer = decompose && mDecomposer ? &*mDecomposer : nullptr;
    const Plan& plan = session.plan();
    // A setting that rebinds what an error measures (--sweep ERROR.source=…) has other sources to
    // take apart than the decomposer was made for: it is not taken apart.
    if (decomposer) {
        const auto here = decompositionTargets(plan, mMeasuredBuffers);
        auto same = [](const DecompositionTarget& a, const DecompositionTarget& b) {
            return a.errorNode == b.errorNode && a.source == b.source && a.tracer == b.tracer;
        };
        if (!std::equal(here.begin(), here.end(), decomposer->targets().begin(),
                        decomposer->targets().end(), same))
            decomposer = nullptr;
    }
    // A sequence (--frames) runs frame after frame with the temporal passes' history, as `run`
    // does; each frame's buffers are read once. Times are per frame; errors are the last frame's.
    const std::vector<int>& frames = session.frames();
    KeepingSink sink;

    std::vector<std::vector<double>> stepSeconds(plan.steps.size()), stepGpuSeconds(plan.steps.size());
    std::vector<double> frameSeconds;
    // error_measure step → its RMSE on each frame of the last run
    std::map<std::size_t, std::vector<double>> rmseByFrame;
    FrameReport last;
    for (int r = 0; r < opt.warmup + opt.runs; ++r) {
        const bool lastRun = r + 1 == opt.warmup + opt.runs;
        mFrames.cut();  // each run is the sequence from its first frame
        for (std::size_t i = 0; i < frames.size(); ++i) {
            sink.keep = lastRun && i + 1 == frames.size();
            last = mFrames.run(plan, frames[i], sink).report;
            if (r >= opt.warmup) {
                frameSeconds.push_back(last.seconds);
                for (std::size_t s = 0; s < last.passes.size(); ++s) {
                    stepSeconds[s].push_back(last.passes[s].seconds);
                    if (last.passes[s].gpuSeconds)
                        stepGpuSeconds[s].push_back(*last.passes[s].gpuSeconds);
                }
            }
            if (lastRun && frames.size() > 1)
                for (std::size_t s = 0; s < last.passes.size(); ++s)
                    if (auto it = last.passes[s].metrics.find("rmse");
                        plan.steps[s].io.roles.measuresError && it != last.passes[s].metrics.end())
                        rmseByFrame[s].push_back(it->second);
        }
        logProgress(100 * ++mRunsDone / std::max(1, mTotalRuns));
    }

    BenchSetting setting;
    setting.label = sweepLabel(point);
    setting.frame = TimingStats::of(frameSeconds);
    setting.peakBytes = last.peakBytes;
    for (std::size_t s = 0; s < plan.steps.size(); ++s) {
        const PlanStep& step = plan.steps[s];
        PassTiming t{step.name, step.type, step.io.workUnit, 0, TimingStats::of(stepSeconds[s]), {},
                     step.io.roles.measuresError};
        if (!stepGpuSeconds[s].empty())
            t.gpuSeconds = TimingStats::of(stepGpuSeconds[s]);
        if (auto it = last.passes[s].work.find(t.unit); it != last.passes[s].work.end())
            t.work = it->second;
        setting.passes.push_back(t);
        if (!step.io.roles.measuresError)
            continue;
        ErrorNodeResult e = errorNodeResult(step, last.passes[s]);
        for (const auto& w : plan.warnings)
            if (w.pointer == step.pointer) e.warnings.push_back(w.message);
        if (auto it = rmseByFrame.find(s); it != rmseByFrame.end())
            e.rmseByFrame = it->second;
        if (auto src = step.inputs.find("source"); src != step.inputs.end())
            for (const int u : upstreamSteps(plan, src->second)) {
                e.methodPasses.push_back(plan.steps[std::size_t(u)].name);
                const PassTiming& timed = setting.passes[std::size_t(u)];  // u < s: made already
                e.methodSeconds += timed.gpuSeconds ? timed.gpuSeconds->median : timed.seconds.median;
            }
        if (!opt.html.empty())
            e.images = errorImages(step.name + ".heat", e, mFrames.source(frames.back()), sink,
                                   session.inputs());
        setting.errors.push_back(e);
    }
    if (decomposer)
        decomposer->decompose(sessionOptions, sink.images, setting.label, setting.errors);
    if (std::any_of(plan.steps.begin(), plan.steps.end(),
                    [](const PlanStep& s) { return s.io.roles.tracesRays; }))
        addBareRayLoops(plan, mFrames, frames.back(), opt, setting);
    return setting;
}



IncrementalTiming Bencher::measureIncremental(const std::string& change) {
    const SweepAxis axis = parseSweep(change);
    if (axis.values.size() < 2)
        throw UsageError(fmt::format("--incremental {}: give two values or more to alternate "
                                     "between",
                                     change));
    IncrementalTiming t;
    t.setting = axis.name;
    for (const auto& v : axis.values) t.values.push_back(valueText(v));
    SetupOptions options = mOptions.session;
    options.frames = std::to_string(mProbe.frames().back());
    Session session(options);
    auto set = [&, kind = kindOf(axis.name)](const nlohmann::json& value) {
        Settings next = session.settings();
        applySetting(next, kind, axis.name, value);
        session.replaceSettings(std::move(next));
    };
    const int frame = mProbe.frames().back();
    std::vector<double> whole, rerun;
    std::size_t next = 0;
    set(axis.values[next]);
    session.run(frame);  // reads the capture's buffers once
    for (int r = 0; r < mOptions.warmup + mOptions.runs; ++r) {
        // A whole frame (the buffers in memory, as bench times every setting), then a change.
        session.forgetOutputs();
        const double full = session.run(frame).report.seconds;
        next = (next + 1) % axis.values.size();
        set(axis.values[next]);
        const FrameResult again = session.run(frame);
        if (r >= mOptions.warmup) {
            whole.push_back(full);
            rerun.push_back(again.report.seconds);
        }
        t.passes = int(again.report.passes.size());
        t.executed.clear();
        for (const auto& p : again.report.passes)
            if (!p.reused) t.executed.push_back(p.name);
    }
    t.frame = TimingStats::of(whole);
    t.rerun = TimingStats::of(rerun);
    return t;
}

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
                axis.values.push_back(v);
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
        axis.values.push_back(Settings::valueFromText(v));
        if (comma == std::string::npos)
            break;
        start = comma + 1;
    }
    return axis;
}

std::string valueText(const nlohmann::json& value) {
    return value.is_string() ? value.get<std::string>() : value.dump();
}

std::string SweepAxis::text() const {
    std::vector<std::string> texts;
    for (const auto& v : values) texts.push_back(valueText(v));
    return fmt::format("{}={}", name, fmt::join(texts, ","));
}

std::vector<SweepPoint> sweepGrid(const std::vector<SweepAxis>& axes) {
    std::vector<SweepPoint> grid = {{}};
    for (const auto& axis : axes) {
        if (axis.values.empty())
            throw UsageError(fmt::format("sweep {}: no values", axis.name));
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

std::string sweepLabel(const SweepPoint& point) {
    std::string label;
    for (const auto& [name, value] : point)
        label += (label.empty() ? "" : " ") + name + "=" + valueText(value);
    return label.empty() ? "default" : label;
}

Bencher::Bencher(const BenchOptions& options) : mOptions(options), mProbe(options.session) {
    for (const auto& w : mProbe.plan().warnings)
        if (mWarned.insert(w.pointer + ": " + w.message).second)
            logWarning(w.pointer + ": " + w.message);
    mBase = options.session;
}

BenchResult Bencher::emptyResult() const {
    BenchResult result;
    result.config = mOptions.session.config;
    result.capture = mProbe.capturePath(mProbe.frames().back());
    result.frame = mProbe.frames().back();
    result.frames = mProbe.frames();
    result.extent = mProbe.extent();
    result.runs = mOptions.runs;
    result.warmup = mOptions.warmup;
    result.device = mProbe.plan().device == Device::Cuda ? "cuda" : "cpu";
    for (const auto& axis : mOptions.sweeps) result.sweeps.push_back(axis.text());
    result.threads =
        int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    return result;
}

SettingKind settingKind(const GraphDesc& graph, const std::string& name) {
    if (isCvarName(name)) return SettingKind::Cvar;
    const auto dot = name.find('.');
    if (dot == std::string::npos) return SettingKind::Param;  // the planner says what is wrong
    for (const auto& n : graph.nodes)
        if (n.name == name.substr(0, dot))
            return builtinParam(n.type, name.substr(dot + 1)) || !builtinPasses().find(n.type)
                       ? SettingKind::Param
                       : SettingKind::Input;
    return SettingKind::Param;
}

void applySetting(Settings& settings, SettingKind kind, const std::string& name,
                  const nlohmann::json& value) {
    if (kind == SettingKind::Cvar) settings.setCvar(name, value);
    else if (kind == SettingKind::Param) settings.setParam(name, value);
    else if (!value.is_string())
        throw UsageError(fmt::format("{}: rebinds an input, so its values are sources' names "
                                     "(pass.port or capture:Buffer), not {}",
                                     name, value.dump()));
    else settings.setInput(name, value.get<std::string>());
}

std::vector<const NodeDesc*> errorMeasureNodes(const GraphDesc& graph) {
    std::vector<const NodeDesc*> nodes;
    for (const auto& n : graph.nodes)
        if (const PassType* type = builtinPasses().find(n.type); type && type->roles.measuresError)
            nodes.push_back(&n);
    return nodes;
}

BenchResult runBench(const BenchOptions& options, const std::string& incremental) {
    const std::vector<SweepPoint> grid = sweepGrid(options.sweeps);
    Bencher bencher(options);
    bencher.expectRuns(int(grid.size()) * (options.warmup + options.runs));
    BenchResult result = bencher.emptyResult();
    for (const auto& point : grid) result.settings.push_back(bencher.measure(point, true));
    result.markPareto();
    if (!incremental.empty()) result.incremental = bencher.measureIncremental(incremental);
    return result;
}

}  // namespace fp::app
