#include "app/RunSetup.h"

#include "app/Invocation.h"
#include "io/ExrReader.h"
#include "io/FramePattern.h"
#include "foundation/Error.h"

#include <OpenEXR/ImfIntAttribute.h>

#include <filesystem>
#include <fstream>
#include <set>

namespace fp::app {

namespace {
std::pair<std::string, std::string> splitAssignment(const std::string& text, const char* flag) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0)
        throw UsageError(fmt::format("{} {}: expected NAME=VALUE", flag, text));
    return {text.substr(0, eq), text.substr(eq + 1)};
}

std::string trimmed(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// A cvar as Unreal's console takes it: "r.SSGI.Quality 4", or NAME=VALUE.
std::pair<std::string, std::string> splitCvar(const std::string& text) {
    const std::string t = trimmed(text);
    const auto eq = t.find('=');
    const auto space = t.find_first_of(" \t");
    if (eq == std::string::npos && space != std::string::npos && space > 0)
        return {t.substr(0, space), trimmed(t.substr(space))};
    auto [name, value] = splitAssignment(t, "--cvar");
    return {trimmed(name), trimmed(value)};
}
}  // namespace

std::vector<std::string> readCvarsFile(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw UsageError(fmt::format("--cvars {}: cannot read the file", path));
    // Unreal's .ini: cvars under [SystemSettings] or [ConsoleVariables] (what `tune` prints),
    // "; comments", NAME=VALUE lines. Keys of other sections are not cvars and are skipped.
    std::vector<std::string> out;
    std::string line, section;
    std::set<std::string> skipped;
    for (int number = 1; std::getline(in, line); ++number) {
        const std::string t = trimmed(line);
        if (t.empty() || t[0] == ';' || t[0] == '#') continue;
        if (t.front() == '[') {
            if (t.back() != ']')
                throw UsageError(fmt::format("--cvars {}:{}: '{}' is not a [Section]", path,
                                             number, t));
            section = t.substr(1, t.size() - 2);
            continue;
        }
        if (section != "SystemSettings" && section != "ConsoleVariables") {
            skipped.insert(section.empty() ? "(before any section)" : "[" + section + "]");
            continue;
        }
        const auto eq = t.find('=');
        if (eq == std::string::npos || eq == 0)
            throw UsageError(fmt::format("--cvars {}:{}: expected NAME=VALUE, got '{}'", path,
                                         number, t));
        out.push_back(trimmed(t.substr(0, eq)) + "=" + trimmed(t.substr(eq + 1)));
    }
    for (const auto& s : skipped)
        logWarning(fmt::format("--cvars {}: lines of {} skipped: cvars are read from "
                               "[SystemSettings] and [ConsoleVariables]",
                               path, s));
    return out;
}


RunSetup::RunSetup(const SetupOptions& o)
    : mConfig(io::loadRunConfig(o.config)),
      mInputs(std::make_shared<SessionInputs>(o.config, mConfig)),
      mProfile(o.profile.empty()
                   ? io::CaptureProfile::fromJson(mConfig.profile, o.config + ": /profile")
                   : io::CaptureProfile::load(o.profile)) {
    for (const auto& file : o.cvarFiles)
        for (auto& c : readCvarsFile(file)) mFileCvars.push_back(std::move(c));
    if (!o.capture.empty())
        mConfig.capture = o.capture;
    if (o.memoryCapture) {
        mMemory = o.memoryCapture;
        mConfig.capture = mMemory->name();
        mConfig.previous.clear();
        mConfig.camera.clear();
    }
    if (!o.previous.empty())
        mConfig.previous = o.previous;
    plan(o);
    if (!mConfig.previous.empty()) {
        if (mFrames.size() != 1)
            throw UsageError(fmt::format("--previous {}: names the frame before one capture, but "
                                         "this run has {} frames (a sequence finds frame N−1 "
                                         "itself)",
                                         mConfig.previous, mFrames.size()));
        if (!std::filesystem::exists(mConfig.previous) && mProfile.filePattern().empty())
            throw UsageError(fmt::format("--previous {}: no such file", mConfig.previous));
    }
    // Several frames of one file: each frame reads the same pixels (and temporal passes
    // accumulate one image), which is rarely what a frame list means.
    if (mFrames.size() > 1 && !io::FramePattern(mConfig.capture).hasFrameToken() &&
        mProfile.filePattern().empty())
        logWarning(fmt::format("capture '{}' is one file without a frame token: each of the {} "
                               "frames reads it (a sequence is a pattern, e.g. shot.####.exr)",
                               mConfig.capture, mFrames.size()));
}

RunSetup::RunSetup(const RunSetup& base, const SetupOptions& o)
    : mConfig(base.mConfig),
      mInputs(base.mInputs),
      mProfile(base.mProfile),
      mFileCvars(base.mFileCvars),
      mMemory(base.mMemory),
      mHeader(base.mHeader) {
    plan(o);
}

RunSetup::RunSetup(const RunSetup& base, io::RunConfig config, const SetupOptions& o)
    : mConfig(std::move(config)),
      mInputs(base.mInputs),
      mProfile(base.mProfile),
      mFileCvars(base.mFileCvars),
      mMemory(base.mMemory),
      mHeader(base.mHeader) {
    plan(o);
}

void RunSetup::plan(const SetupOptions& o) {
    PlanInputs inputs;
    inputs.priorErrors = mConfig.errors;
    if (mConfig.capture.empty())
        inputs.priorErrors.push_back(
            {"/capture", "the config names no capture (a file or pattern)"});
    std::vector<std::string> cvars = mFileCvars;
    cvars.insert(cvars.end(), o.cvars.begin(), o.cvars.end());
    for (const auto& c : cvars) {
        auto [name, value] = splitCvar(c);
        inputs.overrides.cvars[name] = io::parseCliValue(value);
    }
    for (const auto& s : o.sets) {
        auto [name, value] = splitAssignment(s, "--set");
        inputs.overrides.sets.emplace_back(name, io::parseCliValue(value));
    }
    inputs.overrides.dumps = o.dumps;
    inputs.allowUnknownCvars = o.allowUnknownCvars;
    inputs.overrides.device = o.device;
    inputs.overrides.runEveryPass = o.runEveryPass;
    inputs.overrides.dumpsOnly = o.dumpsOnly;

    const io::FramePattern pattern(mConfig.capture);
    // A capture in memory is one frame, numbered as it was made.
    const std::string spec = mMemory                   ? std::to_string(mMemory->frame())
                             : !o.frames.empty()       ? o.frames
                             : !mConfig.frames.empty() ? mConfig.frames
                                                       : pattern.inlineFrames();
    if (!spec.empty()) {
        mFrames = io::parseFrameSpec(spec);
    } else if (pattern.hasFrameToken()) {
        throw UsageError(
            fmt::format("{}: capture '{}' is a frame pattern; give --frames or "
                        "\"frames\"",
                        o.config, mConfig.capture));
    }
    const std::string first = mFrames.empty() ? mConfig.capture : pattern.path(mFrames.front());
    // What the planner needs of the first capture's header, read once and shared with the setups
    // made from this one (a session re-plans after every change; a sweep once per setting).
    if (!mHeader || mHeader->path != first) {
        auto header = std::make_shared<CaptureHeader>();
        header->path = first;
        if (mMemory) {
            header->exists = !mMemory->buffers().empty();
            header->extent = mMemory->extent();
            header->availableBuffers = mMemory->availableBuffers();
            header->truthChannels = mMemory->truthChannels();
            header->frame = int(mMemory->frame());
        } else if (auto files = openCapture(first)) {
            header->exists = true;
            header->extent = files->extent();
            header->availableBuffers = files->availableBuffers();
            header->truthChannels = files->truthChannels();
            // A single capture keeps the frame number it was captured at.
            const auto* f =
                files->primary().header().findTypedAttribute<Imf::IntAttribute>("framepass:frame");
            header->frame = f ? f->value() : 1;
        }
        mHeader = std::move(header);
    }
    if (mHeader->exists) {
        mExtent = mHeader->extent;
        inputs.availableBuffers = mHeader->availableBuffers;
        inputs.truthChannels = mHeader->truthChannels;
        if (mFrames.empty())
            mFrames = {mHeader->frame};
    } else if (mFrames.empty()) {
        mFrames = {1};
    }
    // The light templates repeat per light of the scene: its lights are read (not its meshes).
    if (!mConfig.graph.lightTemplates.empty() && mInputs->hasScene())
        inputs.lightNames = lightNames(mInputs->lights());
    try {
        mPlan = makePlan(mConfig.graph, builtinPasses(), inputs);
    } catch (const UsageError& e) {
        throw UsageError(fmt::format("{}: {}", o.config, e.what()), o.config, e.problems());
    }
    // A bad $OCIO, display or view fails now, before the first frame, not once per frame after
    // the chain ran.
    if (mPlan.needsColorConfig) {
        try {
            const auto colorConfig = mInputs->colorConfig();
            for (const auto& step : mPlan.steps)
                if (step.io.needsColorConfig) {
                    try {
                        step.pass->checkColorConfig(colorConfig);
                    } catch (const Error& e) {
                        throw UsageError(fmt::format("{} ({}): {}", step.pointer, step.name,
                                                     e.what()));
                    }
                }
        } catch (const Error& e) {
            throw UsageError(fmt::format("{}: {}", o.config, e.what()));
        }
    }
}

std::string RunSetup::capturePath(int frame) const {
    return io::FramePattern(mConfig.capture).path(frame);
}

std::string RunSetup::previousCapturePath(int frame) const {
    if (!mConfig.previous.empty()) return mConfig.previous;
    const io::FramePattern pattern(mConfig.capture);
    return pattern.hasFrameToken() ? pattern.path(frame - 1) : "";
}

std::optional<io::CaptureFiles> RunSetup::openCapture(const std::string& path) const {
    if (path.empty()) return std::nullopt;
    // A single-file capture that is not there yet is planned without it (plan before capture).
    if (mProfile.filePattern().empty() && !std::filesystem::exists(path)) return std::nullopt;
    try {
        return std::make_optional<io::CaptureFiles>(path, mProfile);
    } catch (const UsageError&) {
        throw;
    } catch (const Error&) {
        if (mProfile.filePattern().empty()) throw;
        return std::nullopt;  // no file of the multi-file capture yet
    }
}

io::CaptureSource::Options RunSetup::captureOptions(int frame) const {
    io::CaptureSource::Options o;
    o.path = capturePath(frame);
    o.previousPath = previousCapturePath(frame);
    o.frame = frame;
    o.cameraSidecar = cameraPath(frame);
    if (!mConfig.camera.empty() && io::FramePattern(mConfig.camera).hasFrameToken())
        o.previousCameraSidecar = cameraPath(frame - 1);
    SessionInputs* inputs = mInputs.get();
    o.scene = [inputs]() -> const io::SceneFile& { return inputs->scene(); };
    o.lights = [inputs]() -> const std::vector<Light>& { return inputs->lights(); };
    o.rayScene = [inputs](const Vec3d& origin) { return inputs->rayScene(origin); };
    if (inputs->hasScene())  // without a scene there is no sky light (and it is no error)
        o.environment = [inputs]() -> const Environment& { return inputs->environment(); };
    o.colorConfig = [inputs]() { return inputs->colorConfig(); };
    return o;
}

std::string RunSetup::cameraPath(int frame) const {
    return mConfig.camera.empty() ? "" : io::FramePattern(mConfig.camera).path(frame);
}

}  // namespace fp::app
