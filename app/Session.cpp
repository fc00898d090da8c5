#include "app/Session.h"

#include "foundation/Error.h"
#include "foundation/Suggest.h"
#include "framework/CvarTable.h"
#include "framework/SemanticBuffers.h"
#include "io/ConfigLoader.h"

#include <algorithm>

namespace fp::app {

Session::Session(SetupOptions options)
    : mOptions([&] {
          options.dumps.clear();
          return options;
      }()),
      mBase(mOptions),
      mFrames(mBase, {.keep = CaptureKeeping::Neighbours, .incremental = true}) {}

Session::~Session() = default;

void Session::replace(std::vector<std::string>& list, const std::string& name,
                      const std::string& value) {
    // The last setting of a name is the one that counts; earlier ones are dropped, so the
    // list stays as short as the settings changed.
    std::erase_if(list, [&](const std::string& s) { return s.substr(0, s.find('=')) == name; });
    list.push_back(name + "=" + value);
}

void Session::setCvar(const std::string& name, const std::string& value) {
    replace(mOptions.cvars, name, value);
    mDirty = true;
}

void Session::setParam(const std::string& passParam, const std::string& value) {
    replace(mOptions.sets, passParam, value);
    mDirty = true;
}

void Session::replaceSettings(std::vector<std::string> cvars, std::vector<std::string> sets) {
    mOptions.cvars = std::move(cvars);
    mOptions.sets = std::move(sets);
    mDirty = true;
}

namespace {
// The built-in passes' cvar table, made once: the registry does not change while running.
const CvarTable& cvarTable() {
    static const CvarTable table(builtinPasses());
    return table;
}
}  // namespace

nlohmann::json Session::cvarValue(const std::string& name) const {
    const CvarTable& table = cvarTable();
    const std::string spelled = table.spelling(name);
    const CvarMapping* mapping = table.find(spelled);
    if (!mapping) {
        const std::vector<std::string> known = table.names();
        throw UsageError(fmt::format("unknown cvar '{}'{}", name, didYouMean(name, known)));
    }
    // The last setting wins: the session's, then the config's.
    for (auto it = mOptions.cvars.rbegin(); it != mOptions.cvars.rend(); ++it) {
        const std::string set = it->substr(0, it->find('='));
        if (table.spelling(set) == spelled) return io::parseCliValue(it->substr(it->find('=') + 1));
    }
    for (const auto& [k, v] : mBase.config().graph.cvars.items())
        if (table.spelling(k) == spelled) return v;
    if (mapping->passType.empty()) return mapping->emulatedValue;
    if (const PassType* type = builtinPasses().find(mapping->passType))
        for (const auto& p : type->params)
            if (p.name == mapping->param) return p.defaultValue;
    return nullptr;
}

std::vector<std::string> Session::cvarNames() const { return cvarTable().names(); }

const RunSetup& Session::setup(const std::vector<std::string>& outputs) {
    if (mDirty || !mPlanned || outputs != mPlannedOutputs) {
        SetupOptions o = mOptions;
        o.dumps = outputs;
        mPlanned.reset();
        mPlanned.emplace(mBase, o);
        mPlannedOutputs = outputs;
        mDirty = false;
    }
    return *mPlanned;
}

FrameResult Session::run(int frame, const std::vector<std::string>& outputs) {
    std::lock_guard<std::mutex> lock(mRunMutex);
    mCancel = false;
    const RunSetup& planned = setup(outputs);

    KeepingSink sink;  // every image it is handed, by layer name
    sink.keep = true;
    const ProgressFn stopBetweenPasses = [this](int done, int total, const PassReport& pass) {
        if (onPass)
            onPass(done, total, pass);
        if (mCancel.load())
            throw Cancelled("cancelled: a newer request replaced this run");
    };
    FrameResult result;
    result.report = mFrames.run(planned.plan(), frame, sink, stopBetweenPasses).report;
    if (outputs.empty() ||
        std::find(outputs.begin(), outputs.end(), "all") != outputs.end()) {
        result.images = std::move(sink.images);
    } else {
        for (const auto& name : outputs) {
            auto it = sink.images.find(name);
            FP_CHECK(it != sink.images.end(), "'{}' was not produced by this run", name);
            result.images[name] = std::move(it->second);
        }
    }
    mLastReport = result.report;
    return result;
}

Image Session::captureBuffer(int frame, const std::string& name) {
    std::lock_guard<std::mutex> lock(mRunMutex);
    if (!mBase.availableBuffers().count(name))
        throw UsageError(fmt::format("the capture has no buffer '{}'", name));
    const SemanticBuffer* sem = findSemanticBuffer(name);
    const int channels = sem ? int(sem->channels.size()) : mBase.truthChannels().at(name);
    return mFrames.source(frame).loadBuffer(name, channels).image();
}

void Session::cancel() { mCancel = true; }

}  // namespace fp::app
