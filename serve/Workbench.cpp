#include "serve/Workbench.h"

#include "app/Settings.h"
#include "app/BenchSweep.h"
#include "app/PlanReport.h"
#include "app/ErrorBreakdown.h"
#include "app/Tune.h"
#include "color/DisplayTransform.h"
#include "foundation/Error.h"
#include "foundation/Suggest.h"
#include "framework/CvarTable.h"
#include "framework/SemanticBuffers.h"
#include "io/ConfigLoader.h"
#include "io/JsonFile.h"

#include <algorithm>
#include <filesystem>

namespace fp::serve {

namespace fs = std::filesystem;

namespace {
// How many events and outcomes are kept for late readers.
constexpr std::size_t kKeptEvents = 512;
constexpr std::size_t kKeptOutcomes = 64;

nlohmann::json paramSpec(const ParamInfo& p) {
    nlohmann::json j = {{"name", p.name}, {"type", p.type}, {"doc", p.doc},
                        {"default", p.defaultValue}};
    if (p.min) j["min"] = *p.min;
    if (p.max) j["max"] = *p.max;
    if (!p.choices.empty()) j["choices"] = p.choices;
    if (!p.cvars.empty()) j["cvars"] = p.cvars;
    if (p.needsHistory) j["needsHistory"] = true;
    return j;
}

std::string absolute(const std::string& path) {
    return path.empty() ? path : fs::absolute(path).lexically_normal().string();
}

// The workbench's plan: every pass runs (the graph shows each with its time and outputs), and
// only the shown outputs are handed back, not the config's files: on the GPU every output handed
// back is a copy to the host.
app::SetupOptions workbenchOptions(app::SetupOptions options) {
    options.runEveryPass = true;
    options.dumpsOnly = true;
    return options;
}

bool isPassOutput(const std::string& name) {
    return name.find('.') != std::string::npos && !isTruthBuffer(name);
}
}  // namespace

Workbench::Workbench(app::SetupOptions options)
    : mOptions(workbenchOptions(std::move(options))), mSession(mOptions) {
    mFrame = mSession.frames().front();
    planned();  // a config that does not plan fails here, not on a request
    mRequested = 1;
    mWorker = std::thread([this] { workerLoop(); });
}

Workbench::~Workbench() {
    stop();
    if (mWorker.joinable()) mWorker.join();
}

void Workbench::stop() {
    {
        std::lock_guard<std::mutex> lock(mStateMutex);
        mStop = true;
    }
    mSession.cancel();
    mChanged.notify_all();
}

bool Workbench::stopped() const {
    std::lock_guard<std::mutex> lock(mStateMutex);
    return mStop;
}

std::shared_ptr<const app::RunSetup> Workbench::planned() { return mSession.setup(shownOutputs()); }

std::vector<std::string> Workbench::shownOutputs() const {
    return std::vector<std::string>(mShown.begin(), mShown.end());
}

void Workbench::event(nlohmann::json e) {
    {
        std::lock_guard<std::mutex> lock(mStateMutex);
        e["seq"] = ++mEventSeq;
        mEvents.emplace_back(mEventSeq, e.dump());
        while (mEvents.size() > kKeptEvents) mEvents.pop_front();
    }
    mChanged.notify_all();
}

void Workbench::workerLoop() {
    uint64_t started = 0;
    for (;;) {
        uint64_t generation = 0;
        {
            std::unique_lock<std::mutex> lock(mStateMutex);
            mChanged.wait(lock, [&] { return mStop || mRequested > started; });
            if (mStop) return;
            generation = started = mRequested;
        }
        runOnce(generation);
    }
}

void Workbench::runOnce(uint64_t generation) {
    Outcome outcome;
    {
        std::lock_guard<std::mutex> session(mSessionMutex);
        const int frame = mFrame;
        mSession.onPass = [&](int done, int total, const PassReport& pass) {
            if (!pass.reused) mLastExecuted[pass.name] = {pass.seconds * 1e3, generation};
            event({{"type", "pass"}, {"generation", generation}, {"done", done}, {"total", total},
                   {"pass", pass.name}, {"ms", pass.seconds * 1e3}, {"reused", pass.reused}});
            std::lock_guard<std::mutex> lock(mStateMutex);
            if (mRequested > generation || mStop) mSession.cancel();  // a newer change waits
        };
        const auto start = std::chrono::steady_clock::now();
        try {
            app::FrameResult r = mSession.run(frame, shownOutputs());
            outcome.ms = std::chrono::duration<double, std::milli>(
                             std::chrono::steady_clock::now() - start)
                             .count();
            mLast = std::move(r);
            mLastFrame = frame;
            mLastGeneration = generation;
            mLastMs = outcome.ms;
            outcome.status = "done";
            event({{"type", "frame"}, {"generation", generation}, {"frame", frame},
                   {"ms", outcome.ms}, {"executed", mLast->report.executedSteps},
                   {"reused", mLast->report.reusedSteps}});
        } catch (const Cancelled&) {
            outcome.status = "cancelled";
            event({{"type", "cancelled"}, {"generation", generation}});
        } catch (const std::exception& e) {
            outcome.status = "error";
            outcome.message = e.what();
            event({{"type", "error"}, {"generation", generation}, {"message", e.what()}});
        }
        mSession.onPass = {};
    }
    {
        std::lock_guard<std::mutex> lock(mStateMutex);
        mFinished = std::max(mFinished, generation);
        mOutcomes[generation] = outcome;
        while (mOutcomes.size() > kKeptOutcomes) mOutcomes.erase(mOutcomes.begin());
    }
    mChanged.notify_all();
}

uint64_t Workbench::apply(const SettingsChange& change, std::vector<Diagnostic>* warnings) {
    // The run in flight stops at its next pass; this change replaces it.
    mSession.cancel("cancelled: a newer request replaced this run");
    {
        std::lock_guard<std::mutex> session(mSessionMutex);
        if (change.frame) {
            const auto& frames = mSession.frames();
            if (std::find(frames.begin(), frames.end(), *change.frame) == frames.end())
                throw RequestError(400, fmt::format("frame {} is not one of the config's frames "
                                                    "({} to {})",
                                                    *change.frame, frames.front(), frames.back()),
                                   "/frame");
        }
        const std::set<std::string> shownBefore = mShown;
        if (change.show) {
            const std::set<std::string> known = knownBuffers();
            for (std::size_t i = 0; i < change.show->size(); ++i)
                if (!known.count((*change.show)[i]))
                    throw RequestError(404,
                                       fmt::format("/show/{}: no buffer '{}' (GET /api/buffers "
                                                   "lists them)",
                                                   i, (*change.show)[i]),
                                       fmt::format("/show/{}", i));
            mShown.clear();
            for (const auto& name : *change.show)
                if (isPassOutput(name)) mShown.insert(name);  // capture buffers need no run
        }
        const app::Settings before = mSession.settings();
        try {
            // Checked by planning: a refused setting leaves the session's as they were.
            app::Settings settings = before;
            settings.merge(change.settings);
            settings.cvarOrigin = change.settings.cvarOrigin;  // named by their place in the body
            settings.setOrigin = change.settings.setOrigin;
            settings.inputOrigin = change.settings.inputOrigin;
            std::vector<Diagnostic> said = mSession.replaceSettings(std::move(settings));
            if (warnings) *warnings = std::move(said);
            planned();
        } catch (const UsageError& e) {
            mShown = shownBefore;
            mSession.replaceSettings(before);
            throw RequestError(400, e.what(),
                               e.problems().empty() ? "" : e.problems().front().pointer);
        }
        if (change.frame) mFrame = *change.frame;
    }
    uint64_t generation;
    {
        std::lock_guard<std::mutex> lock(mStateMutex);
        generation = ++mRequested;
    }
    mChanged.notify_all();
    return generation;
}

nlohmann::json Workbench::waitFor(uint64_t generation) {
    std::unique_lock<std::mutex> lock(mStateMutex);
    mChanged.wait(lock, [&] { return mStop || mFinished >= generation; });
    nlohmann::json j = {{"generation", generation}};
    auto it = mOutcomes.find(generation);
    if (it == mOutcomes.end()) {
        // Never run: a newer change came first (or the server stops).
        j["status"] = mStop ? "stopped" : "cancelled";
        return j;
    }
    j["status"] = it->second.status;
    if (!it->second.message.empty()) j["message"] = it->second.message;
    if (it->second.status == "done") j["ms"] = it->second.ms;
    return j;
}

std::set<std::string> Workbench::knownBuffers() {
    std::set<std::string> names;
    const std::shared_ptr<const app::RunSetup> kept = planned();
    const app::RunSetup& setup = *kept;
    for (const auto& step : setup.plan().steps)
        for (const auto& port : step.io.outputs) names.insert(step.name + "." + port.name);
    for (const auto& b : setup.availableBuffers()) names.insert(b);
    return names;
}

BufferImage Workbench::buffer(const std::string& name, std::optional<int> frame) {
    {
        std::lock_guard<std::mutex> session(mSessionMutex);
        const std::set<std::string> known = knownBuffers();
        if (!known.count(name))
            throw RequestError(404, fmt::format("no buffer '{}'{}: a buffer is PASS.PORT, a "
                                                "capture buffer or a Truth.* layer (GET "
                                                "/api/buffers lists them)",
                                                name,
                                                didYouMean(name, std::vector<std::string>(
                                                                     known.begin(), known.end()))));
    }
    const bool captureBuffer = !isPassOutput(name);
    uint64_t generation;
    {
        std::lock_guard<std::mutex> lock(mStateMutex);
        generation = mRequested;
    }
    // A pass output not shown until now: shown from here on. Its run re-runs only the step that
    // makes it, if that step did not already make it (the step cache).
    SettingsChange show;
    if (!captureBuffer) {
        std::lock_guard<std::mutex> session(mSessionMutex);
        if (!mShown.count(name)) {
            show.show = shownOutputs();
            show.show->push_back(name);
        }
    }
    const bool notShown = show.show.has_value();
    if (notShown) {
        show.frame = frame;
        generation = apply(show);
    }
    bool otherFrame = false;
    if (frame) {
        std::lock_guard<std::mutex> session(mSessionMutex);
        const auto& frames = mSession.frames();
        if (std::find(frames.begin(), frames.end(), *frame) == frames.end())
            throw RequestError(400, fmt::format("?frame={}: not one of the config's frames ({} to "
                                                "{})",
                                                *frame, frames.front(), frames.back()));
        otherFrame = *frame != mFrame;
    }
    if (otherFrame && !captureBuffer && !notShown) {
        // A pass output of another frame: that frame becomes the one shown, and runs.
        SettingsChange change;
        change.frame = frame;
        generation = apply(change);
    }
    BufferImage b;
    b.name = name;
    if (captureBuffer) {
        // Read from the capture: no run needed, whatever the settings.
        std::lock_guard<std::mutex> session(mSessionMutex);
        b.frame = frame.value_or(mFrame);
        b.generation = mLastGeneration;
        b.image = mSession.captureBuffer(b.frame, name);
        const SemanticBuffer* sem = findSemanticBuffer(name);
        b.color = sem ? sem->kind == PortKind::Color : true;  // truth layers are light
        return b;
    }
    // The newest change's run: one a later change cancelled gives way to that change's.
    nlohmann::json outcome = waitFor(generation);
    while (outcome.value("status", "") == "cancelled" && !stopped()) {
        {
            std::lock_guard<std::mutex> lock(mStateMutex);
            generation = mRequested;
        }
        outcome = waitFor(generation);
    }
    if (outcome.value("status", "") == "error")
        throw RequestError(409, fmt::format("the run of change {} failed: {}", generation,
                                            outcome.value("message", "")));
    std::lock_guard<std::mutex> session(mSessionMutex);
    if (!mLast)
        throw RequestError(409, fmt::format("no run has finished yet ({}: {})",
                                            outcome.value("status", ""),
                                            outcome.value("message", "")));
    auto it = mLast->images.find(name);
    if (it == mLast->images.end())
        throw RequestError(409, fmt::format("'{}' is not in the last finished run (generation "
                                            "{}, {}): it did not finish",
                                            name, mLastGeneration, outcome.value("status", "")));
    b.frame = mLastFrame;
    b.generation = mLastGeneration;
    b.image = it->second;  // shares the pixels
    const std::shared_ptr<const app::RunSetup> kept = planned();
    for (const auto& step : kept->plan().steps)
        for (const auto& port : step.io.outputs)
            if (step.name + "." + port.name == name)  // a display's output is drawn as it is
                b.color = port.kind == PortKind::Color && !port.displayReferred;
    return b;
}

nlohmann::json Workbench::graph() {
    std::lock_guard<std::mutex> session(mSessionMutex);
    const std::shared_ptr<const app::RunSetup> kept = planned();
    const app::RunSetup& setup = *kept;
    nlohmann::json j = setup.plan().toJson(setup.extent());
    // Each pass's last executed time: a reused pass keeps the time of the run that made it.
    nlohmann::json times = nlohmann::json::object();
    if (mLast)
        for (const auto& p : mLast->report.passes) {
            nlohmann::json t = {{"reused", p.reused}};
            if (const auto e = mLastExecuted.find(p.name); e != mLastExecuted.end()) {
                t["ms"] = e->second.ms;
                t["generation"] = e->second.generation;
            }
            times[p.name] = t;
        }
    j["times"] = times;
    // How the page draws each buffer: colour through the view, data and display-referred images
    // as they are.
    nlohmann::json kinds = nlohmann::json::object();
    const auto kindName = [](PortKind kind, bool displayReferred) {
        return displayReferred ? "display" : kind == PortKind::Color ? "colour" : "data";
    };
    for (const auto& step : setup.plan().steps)
        for (const auto& port : step.io.outputs)
            kinds[step.name + "." + port.name] = kindName(port.kind, port.displayReferred);
    for (const auto& read : setup.plan().captureReads)
        kinds[read.buffer] = kindName(read.kind, false);
    j["kinds"] = kinds;
    j["generation"] = mLastGeneration;
    j["frame"] = mFrame;
    return j;
}

nlohmann::json Workbench::params() {
    std::lock_guard<std::mutex> session(mSessionMutex);
    const std::shared_ptr<const app::RunSetup> kept = planned();
    const app::RunSetup& setup = *kept;
    std::set<std::string> typesInChain;
    nlohmann::json passes = nlohmann::json::array();
    for (const auto& step : setup.plan().steps) {
        typesInChain.insert(step.type);
        const PassType* type = builtinPasses().find(step.type);
        nlohmann::json list = nlohmann::json::array();
        if (type)
            for (const auto& p : type->params) {
                nlohmann::json spec = paramSpec(p);
                spec["value"] = step.params.value(p.name, p.defaultValue);
                list.push_back(spec);
            }
        passes.push_back({{"name", step.name}, {"type", step.type}, {"params", list}});
    }
    const CvarTable& table = app::builtinCvarTable();
    nlohmann::json cvars = nlohmann::json::array();
    for (const auto& name : mSession.cvarNames()) {
        const CvarMapping* m = table.find(name);
        nlohmann::json c = {{"name", name}, {"value", mSession.cvarValue(name)}};
        if (m && !m->passType.empty()) {
            c["passType"] = m->passType;
            c["param"] = m->param;
            if (const ParamInfo* p = app::builtinParam(m->passType, m->param)) {
                const nlohmann::json spec = paramSpec(*p);
                for (const char* key : {"type", "doc", "default", "min", "max", "choices"})
                    if (spec.contains(key)) c[key] = spec[key];
            }
        } else {
            c["emulated"] = false;
        }
        if (m && !m->note.empty()) c["note"] = m->note;
        bool used = false;
        for (const auto& t : table.targets(name)) used = used || typesInChain.count(t);
        c["inChain"] = used;
        // A cvar whose parameter the config's params (or a set) fix on every pass it reaches
        // has no effect: the page says so beside its slider.
        nlohmann::json pinnedBy = nlohmann::json::array();
        bool free = false;
        for (const auto& step : setup.plan().steps)
            if (const CvarMapping* target = table.find(name, step.type)) {
                const auto pin = step.pinned.find(target->param);
                if (pin == step.pinned.end()) free = true;
                else pinnedBy.push_back(pin->second);
            }
        if (!free && !pinnedBy.empty()) c["shadowedBy"] = pinnedBy;
        cvars.push_back(c);
    }
    uint64_t generation;  // the change these settings are of
    {
        std::lock_guard<std::mutex> lock(mStateMutex);
        generation = mRequested;
    }
    return {{"cvars", cvars},      {"passes", passes},
            {"frames", mSession.frames()}, {"frame", mFrame},
            {"settings", mSession.settings().toJson()}, {"generation", generation}};
}

nlohmann::json Workbench::report() {
    std::lock_guard<std::mutex> session(mSessionMutex);
    if (!mLast) return nullptr;
    nlohmann::json j = mLast->report.toJson();
    j["generation"] = mLastGeneration;
    j["frame"] = mLastFrame;
    j["wallMs"] = mLastMs;
    j["executedSteps"] = mLast->report.executedSteps;
    j["reusedSteps"] = mLast->report.reusedSteps;
    nlohmann::json errors = nlohmann::json::object();
    for (const auto& p : mLast->report.passes)
        if (!p.metrics.empty()) errors[p.name] = p.metrics;
    j["errors"] = errors;
    nlohmann::json executed = nlohmann::json::object();
    for (const auto& [pass, e] : mLastExecuted)
        executed[pass] = {{"ms", e.ms}, {"generation", e.generation}};
    j["lastExecuted"] = executed;
    // Each method's cost beside its error: an error measure's RMSE and the time of the passes
    // its source depends on (their last executed times), not the whole chain's.
    const std::shared_ptr<const app::RunSetup> kept = planned();
    nlohmann::json methods = nlohmann::json::array();
    for (const auto& step : kept->plan().steps) {
        const auto source = step.inputs.find("source");
        if (!step.io.roles.measuresError || source == step.inputs.end() || source->second.fromCapture)
            continue;
        double ms = 0;
        nlohmann::json passes = nlohmann::json::array();
        for (const int s : app::upstreamSteps(kept->plan(), source->second)) {
            const std::string& name = kept->plan().steps[std::size_t(s)].name;
            if (const auto e = mLastExecuted.find(name); e != mLastExecuted.end()) ms += e->second.ms;
            passes.push_back(name);
        }
        nlohmann::json m = {{"measure", step.name}, {"source", source->second.key}, {"ms", ms},
                            {"passes", passes}};
        if (errors.contains(step.name) && errors[step.name].contains("rmse"))
            m["rmse"] = errors[step.name]["rmse"];
        methods.push_back(m);
    }
    j["methods"] = methods;
    return j;
}

nlohmann::json Workbench::status() {
    std::lock_guard<std::mutex> lock(mStateMutex);
    nlohmann::json j = {{"requested", mRequested}, {"finished", mFinished}, {"status", "none"}};
    if (const auto it = mOutcomes.find(mFinished); it != mOutcomes.end()) {
        j["status"] = it->second.status;
        if (!it->second.message.empty()) j["message"] = it->second.message;
    }
    return j;
}

nlohmann::json Workbench::exportSettings() {
    std::lock_guard<std::mutex> session(mSessionMutex);
    const std::shared_ptr<const app::RunSetup> kept = planned();
    const app::RunSetup& setup = *kept;
    const io::RunConfig& rc = setup.config();
    nlohmann::json config = mOptions.config == "-" ? nlohmann::json::object()
                                                   : io::readJsonFile(mOptions.config, "config");
    config["version"] = 1;
    // Paths absolute: the exported file runs from wherever it is saved.
    if (!rc.capture.empty()) config["capture"] = absolute(rc.capture);
    for (const auto& [key, path] : {std::pair<const char*, std::string>{"scene", rc.scene},
                                    {"camera", rc.camera},
                                    {"previous", rc.previous}})
        if (!path.empty()) config[key] = absolute(path);
    if (!rc.ocioConfig.empty()) config["color"]["ocioConfig"] = absolute(rc.ocioConfig);
    if (config.contains("profile") && config["profile"].is_string() &&
        config["profile"].get<std::string>().ends_with(".json"))
        config["profile"] = absolute((fs::path(rc.baseDir) / config["profile"].get<std::string>())
                                         .string());
    if (!mOptions.profile.empty()) config["profile"] = mOptions.profile;
    if (!mOptions.device.empty()) config["device"] = mOptions.device;
    app::SweepPoint cvarPoint;
    const app::Settings settings = mSession.settings();
    for (const auto& [name, value] : settings.cvars.items()) {
        config["cvars"][name] = value;
        cvarPoint.emplace_back(name, value);
    }
    for (const auto& [target, value] : settings.sets) config["set"][target] = value;
    for (const auto& [target, source] : settings.inputs) config["inputs"][target] = source;
    config["frames"] = std::to_string(mFrame);
    return {{"config", config}, {"ini", app::systemSettings(cvarPoint)}};
}

nlohmann::json Workbench::breakdown(int rays) {
    if (rays < 1 || rays > app::kMaxBreakdownRays)
        throw RequestError(400, fmt::format("?rays={}: 1 to {}", rays, app::kMaxBreakdownRays));
    uint64_t started;  // the newest change, which the breakdown is of
    {
        std::unique_lock<std::mutex> lock(mStateMutex);  // the newest change first
        started = mRequested;
        mChanged.wait(lock, [&] { return mStop || mFinished >= started; });
    }
    // One breakdown at a time. It holds the session only to take what it needs, so settings
    // change while it runs (and a change cancels it: its figures would be of settings gone).
    std::lock_guard<std::mutex> one(mBreakdownMutex);
    const uint64_t cancels = mBreakdownCancels.load();
    const auto start = std::chrono::steady_clock::now();
    std::shared_ptr<const app::RunSetup> current;
    std::vector<app::DecompositionTarget> targets;
    std::map<std::string, Image> kept;
    std::vector<app::ErrorNodeResult> errors;
    app::SetupOptions options;
    int frame = 0;
    nlohmann::json out = {{"rays", rays}, {"errors", nlohmann::json::array()}};
    {
        std::lock_guard<std::mutex> session(mSessionMutex);
        if (!mLast) throw RequestError(409, "no run has finished yet");
        out["generation"] = mLastGeneration;
        const std::shared_ptr<const app::RunSetup> shown = planned();
        targets = app::decompositionTargets(shown->plan(), shown->availableBuffers());
        if (targets.empty()) return out;
        // The measured sources, handed back by a run that executes nothing (the step cache has
        // them) where the page does not show them.
        kept = mLast->images;
        std::vector<std::string> outputs = shownOutputs();
        for (const auto& t : targets)
            if (!kept.count(t.source)) outputs.push_back(t.source);
        if (outputs.size() > mShown.size()) {
            app::FrameResult sources = mSession.run(mLastFrame, outputs);
            for (auto& [name, image] : sources.images) kept.emplace(name, std::move(image));
        }
        current = planned();
        const Plan& plan = current->plan();
        for (std::size_t i = 0; i < plan.steps.size() && i < mLast->report.passes.size(); ++i)
            if (plan.steps[i].io.roles.measuresError)
                errors.push_back(app::errorNodeResult(plan.steps[i], mLast->report.passes[i]));
        options = mSession.options();
        frame = mLastFrame;
    }
    // Its own driver: the session's runs go on beside it with theirs.
    app::FrameDriver frames(*current, {.keep = app::CaptureKeeping::Neighbours});
    app::ErrorBreakdown taker(*current, frames, std::move(targets), rays, frame);
    taker.onPass = [&](int, int, const PassReport&) {
        if (mBreakdownCancels.load() != cancels)
            throw Cancelled("cancelled by DELETE /api/breakdown");
        std::lock_guard<std::mutex> lock(mStateMutex);
        if (mStop) throw Cancelled("the server is stopping");
        if (mRequested != started)
            throw Cancelled(fmt::format("change {} replaced the settings it was of", mRequested));
    };
    try {
        taker.decompose(options, kept, "workbench", errors);
    } catch (const Cancelled& c) {
        throw RequestError(409, fmt::format("the breakdown was cancelled: {}", c.what()));
    }
    for (const auto& e : errors) {
        nlohmann::json j = {{"name", e.name}, {"metrics", e.metrics}};
        if (e.decomposition) {
            j["decomposition"] = e.decomposition->toJson();
            j["text"] = app::decompositionText(*e.decomposition);
        }
        out["errors"].push_back(j);
    }
    out["ms"] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                    .count();
    return out;
}

nlohmann::json Workbench::cancelBreakdown() {
    ++mBreakdownCancels;
    return {{"status", "cancelled"}};
}

nlohmann::json Workbench::bufferNames() {
    std::lock_guard<std::mutex> session(mSessionMutex);
    const std::shared_ptr<const app::RunSetup> kept = planned();
    const app::RunSetup& setup = *kept;
    nlohmann::json passes = nlohmann::json::array(), capture = nlohmann::json::array(),
                   truth = nlohmann::json::array();
    for (const auto& step : setup.plan().steps)
        for (const auto& port : step.io.outputs) passes.push_back(step.name + "." + port.name);
    for (const auto& b : setup.availableBuffers())
        (isTruthBuffer(b) ? truth : capture).push_back(b);
    return {{"passes", passes}, {"capture", capture}, {"truth", truth}};
}

nlohmann::json Workbench::displays() {
    std::lock_guard<std::mutex> session(mSessionMutex);
    const auto config = planned()->inputs().colorConfig();
    nlohmann::json list = nlohmann::json::array();
    for (int d = 0; d < config->getNumDisplays(); ++d) {
        const char* display = config->getDisplay(d);
        nlohmann::json views = nlohmann::json::array();
        for (int v = 0; v < config->getNumViews(display); ++v)
            views.push_back(config->getView(display, v));
        list.push_back({{"display", display}, {"views", views},
                        {"defaultView", config->getDefaultView(display)}});
    }
    return {{"displays", list}, {"defaultDisplay", config->getDefaultDisplay()}};
}

OCIO_NAMESPACE::ConstConfigRcPtr Workbench::displayConfig() {
    std::lock_guard<std::mutex> session(mSessionMutex);
    return planned()->inputs().colorConfig();
}

std::optional<Image> Workbench::displayTable(const std::string& view) {
    std::lock_guard<std::mutex> session(mSessionMutex);
    const auto config = planned()->inputs().colorConfig();
    const std::string display = config->getDefaultDisplay();
    if (!view.empty()) {
        bool found = false;
        std::vector<std::string> views;
        for (int v = 0; v < config->getNumViews(display.c_str()); ++v) {
            views.push_back(config->getView(display.c_str(), v));
            found = found || views.back() == view;
        }
        if (!found)
            throw RequestError(404, fmt::format("no view '{}' of display '{}'{}", view, display,
                                                didYouMean(view, views)));
    }
    try {
        return DisplayTransform(config, "scene_linear", display, view, 0.0f, true).halfLut();
    } catch (const Error& e) {
        throw RequestError(400, e.what());
    }
}

std::vector<std::pair<uint64_t, std::string>> Workbench::eventsAfter(
    uint64_t seq, std::chrono::milliseconds wait) {
    std::unique_lock<std::mutex> lock(mStateMutex);
    // A cursor past the last event is another server's (a page reconnecting to a restarted
    // workbench sends the last id it saw): this one's events are all new to it.
    if (seq > mEventSeq) seq = 0;
    mChanged.wait_for(lock, wait, [&] { return mStop || mEventSeq > seq; });
    std::vector<std::pair<uint64_t, std::string>> out;
    for (const auto& e : mEvents)
        if (e.first > seq) out.push_back(e);
    return out;
}

}  // namespace fp::serve
