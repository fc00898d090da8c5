#pragma once
// A look-dev session: one config on one capture, held open while its settings change. The doors
// that are not a single command (the Python module, the server) drive framepass through it.
//
// It reads the config, the capture's header, the scene and the OCIO config once; each setting is
// checked when it is made, by planning the chain with it (a refused one leaves the session as it
// was), and runs return the images asked for in memory. Runs are incremental: the outputs of
// every step are kept (StepCache), so after a change only the steps downstream of it execute
// again, and a frame's buffers are read from disk once. Frames run in order carry the temporal
// passes' history as `run` does; running the same frame again starts from the history it had.
//
// Threads: every member may be called from any thread. Runs take turns; a setting made while a
// run is in flight applies to the next run (the one in flight keeps the plan it started with);
// setup(), lastReport() and the settings read what is current without waiting for the run.
// cancel() stops a run in flight at its next safe point (between passes).
#include "app/FrameDriver.h"
#include "app/RunSetup.h"
#include "app/Settings.h"
#include "framework/Executor.h"

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fp::app {

/// What one run of a frame gave: the report (each pass's time, work, metrics, whether it was
/// reused) and the images asked for, by name ("pass.port" or a capture buffer).
struct FrameResult {
    FrameReport report;
    std::map<std::string, Image> images;  //!< sharing the executor's pixels: no copies
    /// With Session::run's `onDevice`: the outputs a CUDA step made, left on the GPU (sharing
    /// the executor's memory, which stays allocated while one is held); they are not in images.
    std::map<std::string, DeviceImage> deviceImages;
};

class Session {
public:
    /// Reads the config and the first capture's header and plans, as `framepass plan` does;
    /// throws fp::UsageError with the config's problems. `options.dumps` are ignored: each run
    /// names the images it wants. `options.settings`' origins name settings in messages.
    explicit Session(SetupOptions options);
    ~Session();

    /// Sets an Unreal cvar (names in any case, as Unreal's console takes them). Throws
    /// fp::SettingError, the session unchanged, for a cvar framepass does not know or a value it
    /// does not take. Returns (and logs with logWarning) what the change newly warns of: a
    /// config parameter that shadows the cvar, a cvar framepass does not emulate.
    std::vector<Diagnostic> setCvar(const std::string& name, nlohmann::json value);
    /// Sets a pass parameter PASS.PARAM, checked as setCvar is.
    std::vector<Diagnostic> setParam(const std::string& target, nlohmann::json value);
    /// Rebinds input PASS.INPUT to `source` ("pass.port" or "capture:Buffer"), checked as
    /// setCvar is.
    std::vector<Diagnostic> setInput(const std::string& target, std::string source);
    /// Replaces every cvar, parameter and input set so far, checked as one change (named in messages
    /// by the replacement's origins).
    std::vector<Diagnostic> replaceSettings(Settings settings);
    /// The cvars and parameters set so far.
    Settings settings() const;
    /// The options the session was made with, its settings now in them.
    SetupOptions options() const;
    /// The value cvar `name` runs with in this session: the parameter it sets as the plan
    /// resolved it (a config parameter that shadows the cvar wins there too); for a pass the
    /// chain does not run, as set on the session, else as the config's "cvars" give it, else the
    /// parameter's default (a cvar framepass recognises but does not emulate: the value its
    /// chain behaves as; null when there is none). Throws fp::SettingError for an unknown cvar.
    nlohmann::json cvarValue(const std::string& name) const;
    /// Every cvar framepass knows, in its spelling.
    std::vector<std::string> cvarNames() const;

    /// The chain as the current settings plan it; `outputs` are planned as dumps so that they are
    /// computed. Shared: a later change plans anew and leaves this one as it is.
    std::shared_ptr<const RunSetup> setup(const std::vector<std::string>& outputs = {});
    /// The config's frames.
    const std::vector<int>& frames() const { return mBase.frames(); }

    /// Runs `frame` and returns `outputs` ("pass.port", a capture buffer, or "all": every pass
    /// output), with the config's own outputs too. With `onDevice`, the outputs of passes that
    /// ran on the GPU stay there (FrameResult::deviceImages), not copied to the host. Throws
    /// fp::Cancelled when cancel() stopped it.
    FrameResult run(int frame, const std::vector<std::string>& outputs = {}, bool onDevice = false);
    /// Capture buffer or Truth.* layer `name` of `frame`, as the passes read it (through the
    /// profile, sanitised), read once and kept with the frame. Throws fp::UsageError for a
    /// buffer the capture does not have.
    Image captureBuffer(int frame, const std::string& name);
    /// Whether the capture has buffer (or Truth.* layer) `name`.
    bool hasCaptureBuffer(const std::string& name) const;
    /// Forgets the kept outputs: the next run executes every pass (the capture's buffers stay
    /// read).
    void forgetOutputs();
    /// Stops the run in flight at its next safe point with fp::Cancelled(`why`); a run that starts
    /// later is not affected.
    void cancel(std::string why = "cancelled");
    /// Called on the running thread after each pass with (passes done, passes in all, its
    /// report): a door's progress. It may call cancel() or throw to stop the run. Set it before
    /// runs start, not while one is in flight.
    ProgressFn onPass;

    /// The report of the last run that finished.
    std::optional<FrameReport> lastReport() const;

private:
    /// The settings `change` makes of the current ones, planned for the outputs planned last;
    /// on success they become the session's.
    std::vector<Diagnostic> adopt(const std::function<void(Settings&)>& change);
    /// captureBuffer() with the run lock held.
    Image loadCaptureBuffer(int frame, const std::string& name);

    const SetupOptions mOptions;  // as made; mSettings replace its settings when planning
    RunSetup mBase;

    std::mutex mChangeMutex;  // changes and re-plans take turns (held while planning)
    mutable std::mutex mStateMutex;  // guards the four below, briefly: never while planning or running
    Settings mSettings;
    std::shared_ptr<const RunSetup> mPlanned;
    std::vector<std::string> mPlannedOutputs;
    std::optional<FrameReport> mLastReport;

    std::mutex mRunMutex;  // one run at a time
    std::atomic<bool> mCancel{false};
    std::mutex mCancelWhyMutex;
    std::string mCancelWhy;
    // Frames run incrementally, the frame and the one before it kept read.
    FrameDriver mFrames;
};

}  // namespace fp::app
