#include "cli/RunSession.h"

#include "cli/Invocation.h"
#include "io/ExrReader.h"
#include "io/FramePattern.h"
#include "passes/core/Error.h"

#include <OpenEXR/ImfIntAttribute.h>

#include <filesystem>

namespace fp::cli {

namespace {
std::pair<std::string, std::string> splitAssignment(const std::string& text, const char* flag) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0)
        throw UsageError(fmt::format("{} {}: expected NAME=VALUE", flag, text));
    return {text.substr(0, eq), text.substr(eq + 1)};
}
}  // namespace

void SessionOptions::addTo(CLI::App& sub) {
    sub.add_option("config", config, "run config (JSON)")->required();
    sub.add_option("--cvar", cvars,
                   "set an Unreal cvar, e.g. --cvar r.SSGI.LeakFreeReprojection=0");
    sub.add_option("--set", sets, "set a pass parameter, e.g. --set hzb.halfPrecision=false");
    sub.add_option("--dump", dumps, "also write PASS.PORT (or 'all') to <out>/dump/");
    sub.add_option("--frames", frames, "frame spec (overrides the config), e.g. 1001-1010");
    sub.add_option("--capture", capture,
                   "capture file or frame pattern (overrides the config's \"capture\"; relative "
                   "to the working directory)");
    sub.add_option("--profile", profile,
                   "capture profile, a name or FILE.json (overrides the config's \"profile\")");
    sub.add_option("--device", device,
                   "cpu, or cuda: the passes with a CUDA kernel run on the GPU, images stay "
                   "there between them (overrides the config's \"device\")")
        ->check(CLI::IsMember({"cpu", "cuda"}));
    sub.add_flag("--allow-unknown-cvars", allowUnknownCvars,
                 "a cvar framepass does not know (--cvar or the config's \"cvars\") is a "
                 "warning instead of an error");
}

RunSession::RunSession(const SessionOptions& o)
    : mConfig(io::loadRunConfig(o.config)),
      mInputs(std::make_shared<SessionInputs>(o.config, mConfig)),
      mProfile(o.profile.empty()
                   ? io::CaptureProfile::fromJson(mConfig.profile, o.config + ": /profile")
                   : io::CaptureProfile::load(o.profile)) {
    if (!o.capture.empty())
        mConfig.capture = o.capture;
    plan(o);
    // Several frames of one file: each frame reads the same pixels (and temporal passes
    // accumulate one image), which is rarely what a frame list means.
    if (mFrames.size() > 1 && !io::FramePattern(mConfig.capture).hasFrameToken() &&
        mProfile.filePattern().empty())
        logWarning(fmt::format("capture '{}' is one file without a frame token: each of the {} "
                               "frames reads it (a sequence is a pattern, e.g. shot.####.exr)",
                               mConfig.capture, mFrames.size()));
}

RunSession::RunSession(const RunSession& base, const SessionOptions& o)
    : mConfig(base.mConfig), mInputs(base.mInputs), mProfile(base.mProfile) {
    plan(o);
}

RunSession::RunSession(const RunSession& base, io::RunConfig config, const SessionOptions& o)
    : mConfig(std::move(config)), mInputs(base.mInputs), mProfile(base.mProfile) {
    plan(o);
}

void RunSession::plan(const SessionOptions& o) {
    PlanInputs inputs;
    inputs.priorErrors = mConfig.errors;
    if (mConfig.capture.empty())
        inputs.priorErrors.push_back(
            {"/capture", "the config names no capture (a file or pattern)"});
    for (const auto& c : o.cvars) {
        auto [name, value] = splitAssignment(c, "--cvar");
        inputs.overrides.cvars[name] = io::parseCliValue(value);
    }
    for (const auto& s : o.sets) {
        auto [name, value] = splitAssignment(s, "--set");
        inputs.overrides.sets.emplace_back(name, io::parseCliValue(value));
    }
    inputs.overrides.dumps = o.dumps;
    inputs.allowUnknownCvars = o.allowUnknownCvars;
    inputs.overrides.device = o.device;

    const io::FramePattern pattern(mConfig.capture);
    const std::string spec = !o.frames.empty()         ? o.frames
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
    if (auto files = openCapture(first)) {
        mExtent = files->extent();
        inputs.availableBuffers = files->availableBuffers();
        inputs.truthChannels = files->truthChannels();
        if (mFrames.empty()) {
            // A single capture keeps the frame number it was captured at.
            const auto* f =
                files->primary().header().findTypedAttribute<Imf::IntAttribute>("framepass:frame");
            mFrames = {f ? f->value() : 1};
        }
    } else if (mFrames.empty()) {
        mFrames = {1};
    }
    // The light templates repeat per light of the scene: its lights are read (not its meshes).
    if (!mConfig.graph.lightTemplates.empty() && mInputs->hasScene())
        inputs.lightNames = lightNames(mInputs->lights());
    try {
        mPlan = makePlan(mConfig.graph, builtinPasses(), inputs);
    } catch (const UsageError& e) {
        throw UsageError(fmt::format("{}: {}", o.config, e.what()));
    }
}

std::string RunSession::capturePath(int frame) const {
    return io::FramePattern(mConfig.capture).path(frame);
}

std::string RunSession::previousCapturePath(int frame) const {
    const io::FramePattern pattern(mConfig.capture);
    return pattern.hasFrameToken() ? pattern.path(frame - 1) : "";
}

std::optional<io::CaptureFiles> RunSession::openCapture(const std::string& path) const {
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

io::CaptureSource::Options RunSession::captureOptions(int frame) const {
    io::CaptureSource::Options o;
    o.path = capturePath(frame);
    o.previousPath = previousCapturePath(frame);
    o.frame = frame;
    o.cameraSidecar = cameraPath(frame);
    SessionInputs* inputs = mInputs.get();
    o.scene = [inputs]() -> const io::SceneFile& { return inputs->scene(); };
    o.lights = [inputs]() -> const std::vector<Light>& { return inputs->lights(); };
    if (inputs->hasScene())  // without a scene there is no sky light (and it is no error)
        o.environment = [inputs]() -> const Environment& { return inputs->environment(); };
    o.colorConfig = [inputs]() { return inputs->colorConfig(); };
    return o;
}

std::string RunSession::cameraPath(int frame) const {
    return mConfig.camera.empty() ? "" : io::FramePattern(mConfig.camera).path(frame);
}

}  // namespace fp::cli
