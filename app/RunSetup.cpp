#include "app/RunSetup.h"

#include "app/Invocation.h"
#include "app/TruthDefinitions.h"
#include "io/ExrReader.h"
#include "io/FramePattern.h"
#include "foundation/Error.h"

#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <filesystem>

namespace fp::app {

RunSetup::RunSetup(const SetupOptions& o)
    : mConfig(io::loadRunConfig(o.config)),
      mInputs(std::make_shared<SessionInputs>(o.config, mConfig)),
      mProfile(o.profile.empty()
                   ? io::CaptureProfile::fromJson(mConfig.profile, o.config + ": /profile")
                   : io::CaptureProfile::load(o.profile)) {
    for (const auto& file : o.cvarFiles)
        mFileCvars.merge(readCvarsFile(file, o.strict));
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
        // A profile whose last-frame buffers come from the capture itself would never open the
        // file: refused rather than ignored.
        bool readsPrevious = false;
        for (const auto& [buffer, alternatives] : mProfile.buffers())
            for (const auto& m : alternatives) readsPrevious = readsPrevious || !m.previousFrame.empty();
        if (!readsPrevious)
            throw UsageError(fmt::format(
                "--previous {}: the profile '{}' reads no buffer from a previous frame's file "
                "(its PrevSceneColor, TAAHistory and PrevSceneDepth come from the capture "
                "itself), so the file would be ignored; leave --previous out, or choose a "
                "profile that maps a buffer with \"previousFrame\" (blender, blender-direct)",
                mConfig.previous, mProfile.name()));
        // Opened now, through the profile, so a file that is no capture fails before a frame.
        std::optional<io::CaptureFiles> previous;
        try {
            previous = openCapture(mConfig.previous);
        } catch (const Error& e) {
            throw UsageError(fmt::format("--previous {}: not a capture the profile '{}' can read: {}",
                                         mConfig.previous, mProfile.name(), e.what()));
        }
        if (!previous)
            throw UsageError(fmt::format("--previous {}: no capture of the profile '{}' there",
                                         mConfig.previous, mProfile.name()));
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
    Settings settings = mFileCvars;  // the command line's --cvar wins over an .ini's
    settings.merge(o.settings);
    inputs.overrides.cvars = settings.cvars;
    inputs.overrides.sets = settings.sets;
    inputs.overrides.inputs = settings.inputs;
    inputs.overrides.cvarOrigin = o.settings.cvarOrigin;
    inputs.overrides.setOrigin = o.settings.setOrigin;
    inputs.overrides.inputOrigin = o.settings.inputOrigin;
    inputs.overrides.dumps = o.dumps;
    inputs.overrides.dumpOrigin = o.dumpOrigin;
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
            header->truthDefinitions = readTruthDefinitions(files->primary().header());
            // A single capture keeps the frame number it was captured at.
            const auto* f =
                files->primary().header().findTypedAttribute<Imf::IntAttribute>("framepass:frame");
            header->frame = f ? f->value() : 1;
            if (const auto* u = files->primary().header().findTypedAttribute<Imf::DoubleAttribute>(
                    "framepass:sceneUnitsPerMeter"))
                header->unitsPerMeter = u->value();
            const auto* scene =
                files->primary().header().findTypedAttribute<Imf::StringAttribute>("framepass:scene");
            const auto* fingerprint = files->primary().header().findTypedAttribute<Imf::StringAttribute>(
                "framepass:sceneFingerprint");
            if (scene && !scene->value().empty()) {
                header->scene = (std::filesystem::path(first).parent_path() / scene->value())
                                    .lexically_normal()
                                    .string();
                if (fingerprint) header->sceneFingerprint = fingerprint->value();
            }
        }
        mHeader = std::move(header);
    }
    // The capture's units (its header's, as the camera reader takes them, else its profile's),
    // so that a scene in other units is converted when read.
    mInputs->setCaptureUnitsPerMeter(mHeader->unitsPerMeter ? mHeader->unitsPerMeter
                                                            : mProfile.sceneUnitsPerMeter());
    if (mHeader->exists) {
        mExtent = mHeader->extent;
        inputs.availableBuffers = mHeader->availableBuffers;
        inputs.truthChannels = mHeader->truthChannels;
        if (mFrames.empty())
            mFrames = {mHeader->frame};
    } else if (mFrames.empty()) {
        mFrames = {1};
    }
    makeChainPlan(inputs, o.config);
    // A chain that traces rays, a config without a scene, a capture that says its scene: that
    // scene, planned again (its lights expand the light templates, as if the config named it).
    if (mPlan.needsScene && !mInputs->hasScene() && adoptCaptureScene(o.config))
        makeChainPlan(inputs, o.config);
    // An error_measure against a truth of another definition (rt_ambient_occlusion's radius
    // against the capture's Truth.AO radius, SSGI's any-distance AO) says so.
    for (auto& w : truthDefinitionWarnings(mPlan, mHeader->truthDefinitions))
        mPlan.warnings.push_back(std::move(w));
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

void RunSetup::makeChainPlan(PlanInputs inputs, const std::string& configPath) {
    // The light templates repeat per light of the scene: its lights are read (not its meshes).
    if (!mConfig.graph.lightTemplates.empty() && mInputs->hasScene())
        inputs.lightNames = lightNames(mInputs->lights());
    try {
        mPlan = makePlan(mConfig.graph, builtinPasses(), inputs);
    } catch (const UsageError& e) {
        throw UsageError(fmt::format("{}: {}", configPath, e.what()), configPath, e.problems());
    }
}

bool RunSetup::adoptCaptureScene(const std::string& configPath) {
    if (!mHeader || mHeader->scene.empty()) return false;
    if (!std::filesystem::exists(mHeader->scene))
        throw UsageError(fmt::format(
            "{}: a pass traces rays through the scene, and the config names no \"scene\"; the "
            "capture was made from {}, which is not there: add \"scene\": \"path/to/scene.json\"",
            configPath, mHeader->scene));
    mConfig.scene = mHeader->scene;
    const std::optional<double> units = mInputs->captureUnitsPerMeter();
    mInputs = std::make_shared<SessionInputs>(configPath, mConfig);
    mInputs->setCaptureUnitsPerMeter(units);
    logInfo(fmt::format("the config names no \"scene\": using {}, the scene the capture was made "
                        "from",
                        mHeader->scene));
    if (!mHeader->sceneFingerprint.empty() &&
        io::sceneFingerprint(mInputs->description()) != mHeader->sceneFingerprint)
        logWarning(fmt::format("{} (or its geometry) changed since the capture was made; the "
                               "first frame checks that it still lines up with the capture",
                               mHeader->scene));
    return true;
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
    o.alignment = mAlignment;
    return o;
}

std::string RunSetup::cameraPath(int frame) const {
    return mConfig.camera.empty() ? "" : io::FramePattern(mConfig.camera).path(frame);
}

}  // namespace fp::app
