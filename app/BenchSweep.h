#pragma once
// What `bench` and `tune` share: the sweep grid, and timing one setting of it (median of the
// runs, throughput per pass, each error_measure's figures and, where a screen-space error can be
// taken apart, its decomposition).
#include "app/BenchResult.h"
#include "app/ErrorBreakdown.h"
#include "app/RunSetup.h"

#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace fp::app {

/// One point of the grid: (cvar or PASS.PARAM, value) per axis, the values typed as settings are.
using SweepPoint = std::vector<std::pair<std::string, nlohmann::json>>;

/// One axis of a sweep: a cvar or PASS.PARAM and the values it takes.
struct SweepAxis {
    std::string name;
    std::vector<nlohmann::json> values;
    /// NAME=V1,V2,... as --sweep spells it.
    std::string text() const;
};

/// --sweep's text, "NAME=V1,V2,..." or "NAME=A..B" (integers), each value read as --set reads
/// one; fp::UsageError says what is wrong.
SweepAxis parseSweep(const std::string& text);

struct BenchOptions {
    SetupOptions session;
    int runs = 5, warmup = 1;
    std::vector<SweepAxis> sweeps;  //!< the grid's axes, first slowest
    bool json = false;
    std::string html;
    int decomposeRays = 256;  //!< 0: no error decomposition
};

/// A sweep axis or setting names an Unreal cvar ("r.SSGI.Quality") or a pass's parameter or
/// input ("ssgi.halfRes", "gi.source"): cvars are the names that start with "r.".
inline bool isCvarName(const std::string& name) { return name.rfind("r.", 0) == 0; }

/// What a sweep axis names on the chain of `graph`: a cvar, a pass parameter (as --set sets
/// one), or an input (as --input rebinds one: PASS.X where X is no parameter of PASS's type).
enum class SettingKind { Cvar, Param, Input };
SettingKind settingKind(const GraphDesc& graph, const std::string& name);
/// Puts name=value into `settings` as `kind` says; an input's value must be a source's name
/// (fp::UsageError otherwise).
void applySetting(Settings& settings, SettingKind kind, const std::string& name,
                  const nlohmann::json& value);

/// The config's passes whose type measures an error (PassRoles::measuresError), in order: what
/// bench keeps images of and tune aims at.
std::vector<const NodeDesc*> errorMeasureNodes(const GraphDesc& graph);

/// Every combination of the axes' values, first axis slowest.
std::vector<SweepPoint> sweepGrid(const std::vector<SweepAxis>& axes);
/// A value as a setting's text: a string as itself, else its JSON (2, true, 0.5).
std::string valueText(const nlohmann::json& value);
/// "r.SSGI.Quality=2 ssgi.halfRes=true", or "default" for the empty point.
std::string sweepLabel(const SweepPoint& point);

/// Times settings of one config on its capture, one after another.
class Bencher {
public:
    /// Reads the config and the capture's header once; every setting is a new plan of the chain.
    explicit Bencher(const BenchOptions& options);

    /// Times one setting (options.warmup + options.runs runs). `decompose`: also take its
    /// screen-space errors apart (options.decomposeRays > 0).
    BenchSetting measure(const SweepPoint& point, bool decompose);
    /// Times a look-dev session's re-run after `change` ("PASS.PARAM=A,B" or "r.Cvar=A,B"):
    /// one whole frame, then the setting alternated between its values, each re-run executing
    /// only the passes downstream of it (options.warmup + options.runs of each).
    IncrementalTiming measureIncremental(const std::string& change);
    /// Runs done and to do, for the progress line (set the total before measuring).
    void expectRuns(int total) { mTotalRuns = total; }

    const RunSetup& probe() const { return mProbe; }
    /// What sweep axis `name` sets on this chain.
    SettingKind kindOf(const std::string& name) const {
        return settingKind(mProbe.config().graph, name);
    }
    const BenchOptions& options() const { return mOptions; }
    /// The header of a result: config, capture, frame, size, runs, threads.
    BenchResult emptyResult() const;

private:
    BenchOptions mOptions;
    RunSetup mProbe;
    /// Every setting runs the frames here: their buffers are read once for the whole bench.
    FrameDriver mFrames{mProbe, {.keep = CaptureKeeping::Every}};
    SetupOptions mBase;  //!< the command line (each setting adds its error_measure ports as dumps)
    std::optional<ErrorBreakdown> mDecomposer;
    bool mDecomposerChecked = false;
    std::set<std::string> mMeasuredBuffers;  //!< what the measured frame's capture holds
    int mRunsDone = 0, mTotalRuns = 1;
    std::set<std::string> mWarned;  //!< plan warnings already said
};

/// What `bench` does: every point of the sweep grid timed (with its error figures and, where
/// they can be taken apart, their decomposition), the Pareto front marked, and the incremental
/// re-run after `incremental` ("NAME=A,B"; "" = none) timed. The CLI prints it, the Python
/// module returns it.
BenchResult runBench(const BenchOptions& options, const std::string& incremental = "");

}  // namespace fp::app
