#pragma once
// A look-dev session: one config on one capture, held open while its settings change. The doors
// that are not a single command (the Python module, the server) drive framepass through it.
//
// It reads the config, the capture's header, the scene and the OCIO config once; each run plans
// the chain with the session's current cvars and pass parameters (as --cvar and --set) and
// returns the images asked for in memory. Runs are incremental: the outputs of every step are
// kept (StepCache), so after a change only the steps downstream of it execute again, and a
// frame's buffers are read from disk once. Frames run in order carry the temporal passes'
// history as `run` does; running the same frame again starts from the history it had.
// cancel() stops a run in flight from another thread at its next safe point (between passes).
#include "app/FrameDriver.h"
#include "app/RunSetup.h"
#include "framework/Executor.h"

#include <atomic>
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
};

class Session {
public:
    /// Reads the config and the first capture's header and plans, as `framepass plan` does;
    /// throws fp::UsageError with the config's problems. `options.dumps` are ignored: each run
    /// names the images it wants.
    explicit Session(SetupOptions options);
    ~Session();

    /// Sets an Unreal cvar, as --cvar NAME=VALUE (VALUE read as --cvar reads it).
    void setCvar(const std::string& name, const std::string& value);
    /// Sets a pass parameter, as --set PASS.PARAM=VALUE.
    void setParam(const std::string& passParam, const std::string& value);
    /// Replaces every cvar and parameter set so far (each NAME=VALUE): how a door puts back the
    /// settings it had when a change turned out wrong.
    void replaceSettings(std::vector<std::string> cvars, std::vector<std::string> sets);
    /// The cvars and parameters set so far, in order, as NAME=VALUE.
    const SetupOptions& options() const { return mOptions; }
    /// The value of cvar `name` in this session: as set on it, else as the config's "cvars" give
    /// it, else the default of the parameter it sets (or, for a cvar framepass recognises but
    /// does not emulate, the value its chain behaves as; null when there is none). Names match
    /// without regard to case, as in Unreal's console. Throws fp::UsageError for a cvar
    /// framepass does not know.
    nlohmann::json cvarValue(const std::string& name) const;
    /// Every cvar framepass knows, in its spelling.
    std::vector<std::string> cvarNames() const;

    /// The chain as the current settings plan it (re-planned after a change); `outputs` are
    /// planned as dumps so that they are computed.
    const RunSetup& setup(const std::vector<std::string>& outputs = {});
    /// The config's frames.
    const std::vector<int>& frames() const { return mBase.frames(); }

    /// Runs `frame` and returns `outputs` ("pass.port", a capture buffer, or "all": every pass
    /// output), with the config's own outputs too. Throws fp::Cancelled when cancel() stopped it.
    FrameResult run(int frame, const std::vector<std::string>& outputs = {});
    /// Capture buffer or Truth.* layer `name` of `frame`, as the passes read it (through the
    /// profile, sanitised), read once and kept with the frame. Throws fp::UsageError for a
    /// buffer the capture does not have.
    Image captureBuffer(int frame, const std::string& name);
    /// Forgets the kept outputs: the next run executes every pass (the capture's buffers stay
    /// read).
    void forgetOutputs() { mFrames.forgetOutputs(); }
    /// Stops the run in flight at its next safe point; a run that starts later is not affected.
    void cancel();
    /// Called on the running thread after each pass with (passes done, passes in all, its
    /// report): a door's progress. It may call cancel().
    ProgressFn onPass;

    /// The driver the session's frames run through (its captures, kept read): an error breakdown
    /// of the session's frame reads them from here. Not to be used while a run is in flight.
    FrameDriver& frameDriver() { return mFrames; }
    /// The report of the last run that finished.
    const std::optional<FrameReport>& lastReport() const { return mLastReport; }

private:
    static void replace(std::vector<std::string>& list, const std::string& name,
                        const std::string& value);

    SetupOptions mOptions;
    RunSetup mBase;
    std::optional<RunSetup> mPlanned;
    std::vector<std::string> mPlannedOutputs;
    bool mDirty = true;

    std::mutex mRunMutex;  // one run at a time
    std::atomic<bool> mCancel{false};
    // Frames run incrementally, the frame and the one before it kept read.
    FrameDriver mFrames;
    std::optional<FrameReport> mLastReport;
};

}  // namespace fp::app
