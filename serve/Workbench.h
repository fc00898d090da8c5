#pragma once
// The look-dev workbench behind `framepass serve` (docs/serve.md): one library Session held open
// for a browser page and for scripts. It owns the settings, runs the frame after each change on
// a worker thread (one run at a time; a newer change cancels the run in flight), keeps the last
// frame's images and report, and logs progress as events. Every request of the HTTP API is a
// call here; nothing in it knows HTTP.
#include "app/Session.h"
#include "serve/Requests.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace fp::serve {

/// A buffer as the page asks for it, and what it is.
struct BufferImage {
    std::string name;
    int frame = 0;
    uint64_t generation = 0;
    Image image;
    bool color = false;  //!< colour (display-transformed in previews) or data
};

class Workbench {
public:
    /// Plans the config on its capture (fp::UsageError with its problems) and runs the first
    /// frame on the worker thread.
    explicit Workbench(app::SetupOptions options);
    ~Workbench();

    /// The chain as planned: steps with their ports, inputs and device, the culled passes, each
    /// pass's last time and whether it was reused.
    nlohmann::json graph();
    /// Every cvar and pass parameter with its type, range, choices, default, doc and current
    /// value, and the frames.
    nlohmann::json params();
    /// The last finished run: its report (per pass seconds, work, error figures), wall time,
    /// generation and settings, and each pass's last executed time ("lastExecuted": {pass:
    /// {"ms", "generation"}}: a reused pass keeps the time of the run that made its outputs);
    /// null before the first run finishes.
    nlohmann::json report();
    /// Where the runs stand: {"requested", "finished" (generations), "status" of the newest
    /// finished run (done, cancelled, error; "none" before any) and its "message" when it
    /// failed}. Answers at once, a run in flight or not: how a page learns that the first frame
    /// failed.
    nlohmann::json status();
    /// The current settings as a run config (the config's own keys, paths made absolute, its
    /// cvars and "set" merged with the session's) and as an Unreal [SystemSettings] snippet.
    nlohmann::json exportSettings();
    /// Why the last run's errors are what they are: each error measure that can be taken apart
    /// (a screen-space source against a truth layer) as bench takes it apart, with `rays` rays
    /// per pixel for the oracle and the converged tracer ({"errors": [{name, metrics,
    /// decomposition, text}], "rays", "ms"}). Costs an oracle trace and 8 converged traces.
    nlohmann::json breakdown(int rays);
    /// Stops the breakdowns in flight at their next pass (they answer 409); a newer settings
    /// change stops them too.
    nlohmann::json cancelBreakdown();
    /// The names /api/buffer serves: pass outputs, capture buffers and truth layers.
    nlohmann::json bufferNames();
    /// The OCIO displays and views the page may bake, with the defaults.
    nlohmann::json displays();
    /// The display transform of `view` ("" = the config's default) baked as a table over every
    /// half-float value (3 planes of 65536 × 1), as the GPU display kernel uses it; nullopt for
    /// a view with channel crosstalk.
    std::optional<Image> displayTable(const std::string& view);
    /// The session's OCIO config (for PNG previews).
    OCIO_NAMESPACE::ConstConfigRcPtr displayConfig();

    /// Applies a change: checked by planning it first (a bad value throws RequestError 400 and
    /// leaves the settings as they were); cancels the run in flight; starts the run. Returns the
    /// run's generation; `warnings` gets what the change newly warns of (a cvar that a config
    /// parameter shadows, say).
    uint64_t apply(const SettingsChange& change, std::vector<Diagnostic>* warnings = nullptr);
    /// Waits until run `generation` has finished or a newer one replaced it; the outcome as
    /// {"generation", "status": "done"|"cancelled"|"error", "message"?, "ms"?}.
    nlohmann::json waitFor(uint64_t generation);
    /// The buffer `name` of `frame` (default: the current one) with the current settings; runs
    /// what is missing. Throws RequestError 404 for a name the chain does not make.
    BufferImage buffer(const std::string& name, std::optional<int> frame);

    /// The progress events after `seq` (all kept ones for a `seq` past the last: another
    /// server's), waiting up to `wait` for one: each {"seq", "type": "pass"|"frame"|"cancelled"|
    /// "error", …} as JSON text.
    std::vector<std::pair<uint64_t, std::string>> eventsAfter(uint64_t seq,
                                                             std::chrono::milliseconds wait);
    /// Wakes every waiter and stops the worker (the server is shutting down).
    void stop();
    bool stopped() const;

private:
    struct Outcome {
        std::string status;  // done, cancelled, error
        std::string message;
        double ms = 0;
    };
    void workerLoop();
    void runOnce(uint64_t generation);
    void event(nlohmann::json e);
    /// The session's chain as planned now, the shown pass outputs asked for (call with the
    /// session locked).
    std::shared_ptr<const app::RunSetup> planned();
    /// The pass outputs among the shown buffers, as the session's run asks for them.
    std::vector<std::string> shownOutputs() const;
    std::set<std::string> knownBuffers();

    app::SetupOptions mOptions;
    // The session and what its runs gave: used by the worker and by requests, one at a time.
    std::mutex mSessionMutex;
    app::Session mSession;
    std::mutex mBreakdownMutex;  // one breakdown at a time
    std::atomic<uint64_t> mBreakdownCancels{0};  // cancelBreakdown() calls
    int mFrame = 0;
    std::set<std::string> mShown;  //!< pass outputs the page shows: each run hands them back
    std::optional<app::FrameResult> mLast;
    int mLastFrame = 0;
    uint64_t mLastGeneration = 0;
    double mLastMs = 0;
    struct Executed {
        double ms = 0;
        uint64_t generation = 0;
    };
    std::map<std::string, Executed> mLastExecuted;  //!< pass → its last executed run

    // Generations: requested by changes, finished by the worker; events for the page.
    mutable std::mutex mStateMutex;
    std::condition_variable mChanged;
    uint64_t mRequested = 0, mFinished = 0;
    std::map<uint64_t, Outcome> mOutcomes;
    std::deque<std::pair<uint64_t, std::string>> mEvents;
    uint64_t mEventSeq = 0;
    bool mStop = false;
    std::thread mWorker;
};

}  // namespace fp::serve
