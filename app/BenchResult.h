#pragma once
// What `framepass bench` measured: per setting of the sweep grid, each pass's wall times over the
// runs (median, min, max, throughput in the pass's own unit), the frame's, and what every
// error_measure pass reported. Printed as a table, written as JSON or as an HTML report.
#include "foundation/Image.h"

#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace fp::app {

/// Not a pass: the Embree yardstick bench lists with the passes (BareRayLoop.h).
inline constexpr const char* kBareLoopType = "embree";

struct TimingStats {
    double median = 0, min = 0, max = 0;
    static TimingStats of(std::vector<double> seconds);
};

struct PassTiming {
    std::string name, type, unit;  //!< unit: the work counter that measures throughput
    uint64_t work = 0;             //!< of one run
    TimingStats seconds;
    std::optional<TimingStats> gpuSeconds{};  //!< passes run on the GPU: kernel time (CUDA events)
    bool measuresError = false;  //!< an error measure (PassRoles): not part of the chain's time
    /// A pass that traced rays on the CPU: the median times of its own rays' bare Embree loops
    /// one ray at a time (its closest-hit rays through rtcIntersect1, its occlusion rays through
    /// rtcOccluded1) added up — the yardstick of its speed (docs/commands.md, bench).
    std::optional<double> bareSeconds{};
    double throughput() const { return seconds.median > 0 ? double(work) / seconds.median : 0; }
    /// Its bare loops' time over its own: 1 is Embree's speed on its rays with nothing else done.
    double bareRatio() const {
        return bareSeconds && seconds.median > 0 ? *bareSeconds / seconds.median : 0;
    }
};

struct ErrorImages {
    std::string result, truth, heat;  //!< PNG files as base64 (empty when not available)
};

/// One step of an error decomposition: rung `from` against rung `to` (app/ErrorBreakdown.h).
struct DecompositionStepResult {
    std::string name;      //!< "noise", "approximation", "screen-space limit", "multi-bounce"
    std::string from, to;  //!< what the two rungs are (a key, or how it was made)
    double rmse = 0, bias = 0, share = 0;
};

/// Why the error is what it is: the error of an error_measure taken apart (app/ErrorBreakdown.h).
struct ErrorDecompositionResult {
    double rmse = 0, bias = 0;  //!< of the source against the reference
    /// The converged rung's own noise: the RMSE of its seeds' mean about the mean of infinitely
    /// many (their standard error, over every pixel). Steps whose RMSE is not well above it are
    /// noise as much as anything, and the sentence says so.
    double convergedNoiseRmse = 0;
    /// The same of the screen-space oracle's rung (two halves of its rays with two seeds, their
    /// difference); 0 for a ray-traced ladder or an oracle of one ray.
    double oracleNoiseRmse = 0;
    std::vector<DecompositionStepResult> steps;
    std::string sentence;  //!< which step dominates and what would reduce it
    nlohmann::json toJson() const;
};

struct ErrorNodeResult {
    std::string name, source, reference;
    std::map<std::string, double> metrics;  //!< rmse, relMse, ... (ErrorMetrics.h)
    /// A sequence (bench --frames): the RMSE on each frame, with the history of those before
    /// (metrics are the last frame's). Empty for one frame.
    std::vector<double> rmseByFrame;
    ErrorImages images;
    std::optional<ErrorDecompositionResult> decomposition;
    /// The plan's warnings about this measure: a truth of another definition
    /// (app/TruthDefinitions.h), and the like.
    std::vector<std::string> warnings;
    /// The method the measure judges: the passes its source depends on (app::upstreamSteps,
    /// error measures left out; none for a capture buffer) and the sum of their median times
    /// (kernel times for the GPU's): what the method costs a frame, not the whole config's chain.
    std::vector<std::string> methodPasses;
    double methodSeconds = 0;
};

struct BenchSetting {
    std::string label;  //!< "r.SSGI.Quality=2 ssgi.halfRes=true", or "default"
    std::vector<PassTiming> passes;
    TimingStats frame;  //!< all passes of the frame, inputs cached in memory
    std::size_t peakBytes = 0;  //!< most bytes of images held at once in a run (FrameReport)
    std::vector<ErrorNodeResult> errors;
    bool pareto = false;  //!< no other setting is both faster and more accurate
    /// The error the speed-against-error table sorts by: the first error node's RMSE.
    /// The chain's own time: the median of every pass but the error_measure passes (they measure
    /// the frame; Unreal runs none) and the bare Embree loops.
    double chainSeconds() const;
    bool hasError() const { return !errors.empty() && errors.front().metrics.count("rmse"); }
    double error() const { return errors.front().metrics.at("rmse"); }
};

/// A look-dev session's incremental re-run (bench --incremental): after a change of one setting
/// only the passes downstream of it execute; its time beside the whole frame's.
struct IncrementalTiming {
    std::string setting;                  //!< "ssgi_denoise.denoiser"
    std::vector<std::string> values;      //!< the values it alternates between
    TimingStats frame;                    //!< a whole frame, nothing reused
    TimingStats rerun;                    //!< a re-run after the change
    std::vector<std::string> executed;    //!< the passes a re-run executes
    int passes = 0;                       //!< passes in the chain
    nlohmann::json toJson() const;
};

struct BenchResult {
    std::string config, capture;
    std::string device = "cpu";  //!< where the passes with a CUDA kernel ran
    int64_t frame = 0;        //!< the frame whose errors are reported (a sequence's last)
    std::vector<int> frames;  //!< the frames each run goes through, in order
    Extent extent;
    int runs = 0, warmup = 0, threads = 0;
    std::vector<std::string> sweeps;  //!< as given: NAME=V1,V2
    std::vector<BenchSetting> settings;
    std::optional<IncrementalTiming> incremental;

    /// Marks the settings on the Pareto front of (frame median time, error).
    void markPareto();
    nlohmann::json toJson() const;
};

/// The decomposition as bench prints it: each step's RMSE, bias and share, the step biases added
/// up beside the total bias, then the sentence; indented under its error line.
std::string decompositionText(const ErrorDecompositionResult& d);

/// A self-contained HTML page: the table, an SVG plot of time against error, the images.
std::string benchHtml(const BenchResult& result);

}  // namespace fp::app
