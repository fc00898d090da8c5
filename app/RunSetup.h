#pragma once
// A run's setup: the config with the command line (or a session's settings) applied, the frames
// to process and the plan, made after reading only the first capture's header. What `plan`,
// `run`, bench and a Session share.
#include "app/SessionInputs.h"
#include "app/Settings.h"
#include "io/CaptureProfile.h"
#include "io/CaptureSource.h"
#include "io/ConfigLoader.h"
#include "io/MemoryCapture.h"
#include "framework/Planner.h"

#include <map>
#include <memory>
#include <set>
#include <optional>
#include <string>
#include <vector>

namespace fp::app {

struct SetupOptions {
    std::string config;
    Settings settings;               //!< cvars and PASS.PARAM values (--cvar, --set)
    std::vector<std::string> cvarFiles;  //!< Unreal .ini files (--cvars), under the settings
    std::vector<std::string> dumps;  //!< PASS.PORT or all
    std::string dumpOrigin = "--dump {}";  //!< how a message names a dump (PlanOverrides)
    std::string frames;
    std::string capture;  //!< file or frame pattern; overrides the config's "capture"
    std::string profile;  //!< NAME or FILE.json; overrides the config's "profile"
    std::string previous;  //!< the previous frame's capture; overrides the config's "previous"
    bool allowUnknownCvars = false;  //!< an unknown cvar is a warning, not an error
    /// Fail on NaN/Inf/negative input pixels, assumed camera values and a --cvars file that
    /// gives no cvar, instead of sanitizing, assuming or warning (run's --strict).
    bool strict = false;
    std::string device;              //!< cpu or cuda; "" = the config's "device"
    bool runEveryPass = false;       //!< cull no pass (PlanOverrides::runEveryPass)
    bool dumpsOnly = false;          //!< write only the dumps (PlanOverrides::dumpsOnly)
    /// A capture in memory instead of the config's file: one frame, its own number.
    std::shared_ptr<const io::MemoryCapture> memoryCapture;
};

class RunSetup {
public:
    /// Reads the config and the first capture's header, and plans.
    explicit RunSetup(const SetupOptions& options);
    /// The same config planned again with other command-line values (bench's sweep points): the
    /// config and --cvars files are not read again; the scene and OCIO config are shared with
    /// `base`.
    RunSetup(const RunSetup& base, const SetupOptions& options);
    /// Another chain on the same capture, scene and OCIO config as `base` (bench plans the
    /// passes of an error decomposition this way).
    RunSetup(const RunSetup& base, io::RunConfig config, const SetupOptions& options);

    const io::RunConfig& config() const { return mConfig; }
    /// The scene and OCIO config, read once on first use and shared by every frame.
    SessionInputs& inputs() const { return *mInputs; }
    const Plan& plan() const { return mPlan; }
    const io::CaptureProfile& profile() const { return mProfile; }
    const std::vector<int>& frames() const { return mFrames; }
    /// The capture of `frame` (a file, or a multi-file profile's base).
    std::string capturePath(int frame) const;
    /// Frame N−1's capture when the capture is a frame pattern, else "".
    std::string previousCapturePath(int frame) const;
    std::string cameraPath(int frame) const;
    /// How to open `frame`'s capture, with scene and OCIO config coming from inputs().
    io::CaptureSource::Options captureOptions(int frame) const;
    /// Size of the first frame (0×0 when its capture does not exist yet).
    Extent extent() const { return mExtent; }
    /// The buffers the first capture gives (Truth.* layers included); empty when it does not
    /// exist yet.
    const std::set<std::string>& availableBuffers() const { return mHeader->availableBuffers; }
    /// The channel count of each Truth.* layer of the first capture.
    const std::map<std::string, int>& truthChannels() const { return mHeader->truthChannels; }

    /// The capture in memory the session runs on instead of files, or null.
    const std::shared_ptr<const io::MemoryCapture>& memoryCapture() const { return mMemory; }

    /// The capture's files at `path` through the profile, or nothing when none exists yet.
    std::optional<io::CaptureFiles> openCapture(const std::string& path) const;

private:
    void plan(const SetupOptions& options);
    io::RunConfig mConfig;
    std::shared_ptr<SessionInputs> mInputs;
    io::CaptureProfile mProfile;
    Settings mFileCvars;  //!< --cvars files, read once by the first setup
    std::shared_ptr<const io::MemoryCapture> mMemory;
    // The first capture's header as the planner reads it.
    struct CaptureHeader {
        std::string path;
        bool exists = false;
        Extent extent;
        std::set<std::string> availableBuffers;
        std::map<std::string, int> truthChannels;
        /// What each truth layer measures (app/TruthDefinitions.h: layer → quantity → value).
        std::map<std::string, std::map<std::string, double>> truthDefinitions;
        int frame = 1;
        std::optional<double> unitsPerMeter;  //!< the header's framepass:sceneUnitsPerMeter
        /// The scene `framepass capture` made it from (resolved against the capture's folder)
        /// and that scene's fingerprint then (io::sceneFingerprint); empty when not recorded.
        std::string scene, sceneFingerprint;
    };
    /// Makes mPlan from mConfig (the scene's light names expanding the light templates).
    void makeChainPlan(PlanInputs inputs, const std::string& configPath);
    /// A chain that traces rays with no "scene" in its config takes the scene the capture
    /// records; false when it records none.
    bool adoptCaptureScene(const std::string& configPath);
    std::shared_ptr<const CaptureHeader> mHeader;
    /// The scene checked against the capture once for every frame of this setup.
    std::shared_ptr<io::SceneAlignmentCheck> mAlignment = std::make_shared<io::SceneAlignmentCheck>();
    std::vector<int> mFrames;
    Extent mExtent;
    Plan mPlan;
};

}  // namespace fp::app
