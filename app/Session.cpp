#include "app/Session.h"

#include "foundation/Cuda.h"
#include "foundation/Error.h"
#include "foundation/Suggest.h"
#include "app/Invocation.h"
#include "framework/CvarTable.h"
#include "framework/PassRegistry.h"
#include "framework/SemanticBuffers.h"

#include <algorithm>
#include <functional>
#include <set>

namespace fp::app {

Session::Session(SetupOptions options)
    : mOptions([&] {
          options.dumps.clear();
          return options;
      }()),
      mBase(mOptions),
      mSettings(mOptions.settings),
      mFrames(mBase, {.keep = CaptureKeeping::Neighbours, .incremental = true}) {
    mPlanned = std::make_shared<const RunSetup>(mBase, mOptions);
    // What the chain as configured warns of, said once, as `run` says it.
    for (const auto& w : mPlanned->plan().warnings) logWarning(w.pointer + ": " + w.message);
}

Session::~Session() = default;

namespace {

// Whether `value` has the JSON type parameter `p` takes (a number for an int or a float; for a
// bool, Unreal's 0 or 1 too, so that 2 is a bad value rather than a bad type).
bool hasParamType(const ParamInfo& p, const nlohmann::json& value) {
    if (p.type == "bool") return value.is_boolean() || value.is_number_integer();
    if (p.type == "int" || p.type == "float") return value.is_number();
    if (p.type == "string") return value.is_string();
    return true;
}

// The pass type of the pass named `pass` in the config (light templates' copies included).
std::string passTypeOf(const RunSetup& setup, const std::string& pass) {
    for (const auto& d : setup.config().graph.nodes)
        if (d.name == pass) return d.type;
    for (const auto& s : setup.plan().steps)
        if (s.name == pass) return s.type;
    for (const auto& c : setup.plan().culled)
        if (c.name == pass) return c.type;
    return "";
}

// Why the planner refused a cvar: its name is unknown, or its value has the wrong type or range.
SettingError::Kind cvarRefusal(const std::string& name, const nlohmann::json& value) {
    const CvarTable& table = builtinCvarTable();
    const CvarMapping* m = table.find(table.spelling(name));
    if (!m) return SettingError::Kind::UnknownName;
    if (const ParamInfo* p = builtinParam(m->passType, m->param); p && !hasParamType(*p, value))
        return SettingError::Kind::WrongType;
    return SettingError::Kind::BadValue;
}

SettingError::Kind setRefusal(const RunSetup& base, const std::string& target,
                              const nlohmann::json& value) {
    const auto dot = target.find('.');
    if (dot == std::string::npos) return SettingError::Kind::UnknownName;
    const std::string type = passTypeOf(base, target.substr(0, dot));
    if (type.empty()) return SettingError::Kind::UnknownName;
    const ParamInfo* p = builtinParam(type, target.substr(dot + 1));
    if (!p) return SettingError::Kind::UnknownName;
    return hasParamType(*p, value) ? SettingError::Kind::BadValue : SettingError::Kind::WrongType;
}

// Why the planner refused an input's rebinding: the pass or its input is unknown, or the source
// is not one (an unknown name, the wrong number of channels).
SettingError::Kind inputRefusal(const RunSetup& base, const std::string& target) {
    const auto dot = target.find('.');
    if (dot == std::string::npos) return SettingError::Kind::UnknownName;
    const PassType* type = builtinPasses().find(passTypeOf(base, target.substr(0, dot)));
    if (!type) return SettingError::Kind::UnknownName;
    // The ports of a pass made from its defaults: which inputs it has does not hang on a value.
    Diagnostics ignored;
    nlohmann::json params;
    const auto pass = type->create(nlohmann::json::object(), "", ignored, params);
    const std::string port = target.substr(dot + 1);
    const auto& inputs = pass->describe().inputs;
    return std::any_of(inputs.begin(), inputs.end(), [&](const PortSpec& s) { return s.name == port; })
               ? SettingError::Kind::BadValue
               : SettingError::Kind::UnknownName;
}

}  // namespace

std::vector<Diagnostic> Session::adopt(const std::function<void(Settings&)>& change) {
    // Changes take turns (one made meanwhile would be lost otherwise) and plan with no state
    // lock held: planning may log, and a door's log handler may wait for its interpreter's lock
    // while that interpreter's thread waits here to read a report.
    std::lock_guard<std::mutex> turn(mChangeMutex);
    SetupOptions o = mOptions;
    std::shared_ptr<const RunSetup> current;
    {
        std::lock_guard<std::mutex> state(mStateMutex);
        o.settings = mSettings;
        o.dumps = mPlannedOutputs;
        current = mPlanned;
    }
    change(o.settings);
    std::shared_ptr<const RunSetup> planned;
    try {
        planned = std::make_shared<const RunSetup>(mBase, o);
    } catch (const UsageError& e) {
        // Each problem the planner found at one of the settings, said as the door names it.
        std::vector<ConfigProblem> problems;
        std::string message;
        std::optional<SettingError::Kind> kind;
        auto refused = [&](const std::string& where, SettingError::Kind k) {
            for (const auto& p : e.problems())
                if (p.pointer == where) {
                    problems.push_back(p);
                    message += (message.empty() ? "" : "\n") + where + ": " + p.message;
                    if (!kind) kind = k;
                }
        };
        for (const auto& [name, value] : o.settings.cvars.items())
            refused(o.settings.cvarWhere(name), cvarRefusal(name, value));
        for (const auto& [target, value] : o.settings.sets)
            refused(o.settings.setWhere(target), setRefusal(mBase, target, value));
        for (const auto& [target, source] : o.settings.inputs)
            refused(o.settings.inputWhere(target), inputRefusal(mBase, target));
        if (!kind) throw SettingError(SettingError::Kind::BadValue, e.what(), e.problems());
        throw SettingError(*kind, message, std::move(problems));
    }
    // What the change newly warns of (a cvar a config parameter shadows, one not emulated).
    std::set<std::string> before;
    for (const auto& w : current->plan().warnings) before.insert(w.pointer + ": " + w.message);
    std::vector<Diagnostic> news;
    for (const auto& w : planned->plan().warnings)
        if (!before.count(w.pointer + ": " + w.message)) news.push_back(w);
    {
        std::lock_guard<std::mutex> state(mStateMutex);
        mSettings = std::move(o.settings);
        mPlanned = std::move(planned);
    }
    for (const auto& w : news) logWarning(w.pointer + ": " + w.message);
    return news;
}

std::vector<Diagnostic> Session::setCvar(const std::string& name, nlohmann::json value) {
    return adopt([&](Settings& s) { s.setCvar(name, std::move(value)); });
}

std::vector<Diagnostic> Session::setParam(const std::string& target, nlohmann::json value) {
    return adopt([&](Settings& s) { s.setParam(target, std::move(value)); });
}

std::vector<Diagnostic> Session::setInput(const std::string& target, std::string source) {
    return adopt([&](Settings& s) { s.setInput(target, std::move(source)); });
}

std::vector<Diagnostic> Session::replaceSettings(Settings replacement) {
    return adopt([&](Settings& s) { s = std::move(replacement); });
}

Settings Session::settings() const {
    std::lock_guard<std::mutex> state(mStateMutex);
    return mSettings;
}

SetupOptions Session::options() const {
    SetupOptions o = mOptions;
    o.settings = settings();
    return o;
}

nlohmann::json Session::cvarValue(const std::string& name) const {
    const CvarTable& table = builtinCvarTable();
    const std::string spelled = table.spelling(name);
    const CvarMapping* mapping = table.find(spelled);
    if (!mapping)
        throw SettingError(SettingError::Kind::UnknownName,
                           fmt::format("unknown cvar '{}'{}", name, didYouMean(name, table.names())));
    std::lock_guard<std::mutex> state(mStateMutex);
    // The plan's value where the chain runs a pass the cvar sets: what the planner resolved.
    for (const auto& step : mPlanned->plan().steps)
        if (const CvarMapping* m = table.find(spelled, step.type);
            m && !m->passType.empty() && step.params.contains(m->param))
            return step.params[m->param];
    if (const nlohmann::json* set = mSettings.cvar(spelled)) return *set;
    for (const auto& [k, v] : mBase.config().graph.cvars.items())
        if (table.spelling(k) == spelled) return v;
    if (mapping->passType.empty()) return mapping->emulatedValue;
    if (const ParamInfo* p = builtinParam(mapping->passType, mapping->param)) return p->defaultValue;
    return nullptr;
}

std::vector<std::string> Session::cvarNames() const { return builtinCvarTable().names(); }

std::shared_ptr<const RunSetup> Session::setup(const std::vector<std::string>& outputs) {
    std::lock_guard<std::mutex> turn(mChangeMutex);  // planned as a change is (adopt)
    SetupOptions o = mOptions;
    {
        std::lock_guard<std::mutex> state(mStateMutex);
        if (outputs == mPlannedOutputs) return mPlanned;
        o.settings = mSettings;
    }
    o.dumps = outputs;
    auto planned = std::make_shared<const RunSetup>(mBase, o);
    std::lock_guard<std::mutex> state(mStateMutex);
    mPlanned = planned;
    mPlannedOutputs = outputs;
    return planned;
}

FrameResult Session::run(int frame, const std::vector<std::string>& asked, bool onDevice) {
    std::lock_guard<std::mutex> lock(mRunMutex);
    mCancel = false;
    // Capture buffers are read, the rest planned as dumps (a Truth.* layer's name has a dot too).
    std::vector<std::string> outputs, buffers;
    for (const auto& name : asked)
        (hasCaptureBuffer(name) ? buffers : outputs).push_back(name);
    if (!asked.empty() && outputs.empty()) {  // only the capture's buffers: nothing to run
        FrameResult result;
        for (const auto& name : buffers) result.images[name] = loadCaptureBuffer(frame, name);
        return result;
    }
    // The run keeps the plan it starts with: a change made meanwhile plans anew for the next.
    const std::shared_ptr<const RunSetup> planned = setup(outputs);

    KeepingSink sink;  // every image it is handed, by layer name
    sink.keep = true;
    sink.onDevice = onDevice;
    const ProgressFn stopBetweenPasses = [this](int done, int total, const PassReport& pass) {
        if (onPass)
            onPass(done, total, pass);
        if (mCancel.load()) {
            std::lock_guard<std::mutex> why(mCancelWhyMutex);
            throw Cancelled(mCancelWhy);
        }
    };
    FrameResult result;
    result.report = mFrames.run(planned->plan(), frame, sink, stopBetweenPasses).report;
    if (asked.empty() || std::find(outputs.begin(), outputs.end(), "all") != outputs.end()) {
        result.images = std::move(sink.images);
        result.deviceImages = std::move(sink.deviceImages);
    } else {
        for (const auto& name : outputs) {
            if (auto it = sink.deviceImages.find(name); it != sink.deviceImages.end()) {
                result.deviceImages[name] = std::move(it->second);
                continue;
            }
            auto it = sink.images.find(name);
            FP_CHECK(it != sink.images.end(), "'{}' was not produced by this run", name);
            result.images[name] = std::move(it->second);
        }
    }
    for (const auto& name : buffers) result.images[name] = loadCaptureBuffer(frame, name);
    // Nothing downloaded them, so the frame's kernels may still be running: the caller reads
    // the images next, from any stream.
    if (!result.deviceImages.empty()) cuda::synchronize("the outputs left on the GPU");
    std::lock_guard<std::mutex> state(mStateMutex);
    mLastReport = result.report;
    return result;
}

std::optional<FrameReport> Session::lastReport() const {
    std::lock_guard<std::mutex> state(mStateMutex);
    return mLastReport;
}

bool Session::hasCaptureBuffer(const std::string& name) const {
    return mBase.availableBuffers().count(name) > 0;
}

Image Session::captureBuffer(int frame, const std::string& name) {
    std::lock_guard<std::mutex> lock(mRunMutex);
    return loadCaptureBuffer(frame, name);
}

Image Session::loadCaptureBuffer(int frame, const std::string& name) {
    if (!hasCaptureBuffer(name))
        throw UsageError(fmt::format("the capture has no buffer '{}'", name));
    const SemanticBuffer* sem = findSemanticBuffer(name);
    const int channels = sem ? int(sem->channels.size()) : mBase.truthChannels().at(name);
    return mFrames.source(frame).loadBuffer(name, channels).image();
}

void Session::forgetOutputs() {
    std::lock_guard<std::mutex> lock(mRunMutex);
    mFrames.forgetOutputs();
}

void Session::cancel(std::string why) {
    {
        std::lock_guard<std::mutex> lock(mCancelWhyMutex);
        mCancelWhy = std::move(why);
    }
    mCancel = true;
}

}  // namespace fp::app
