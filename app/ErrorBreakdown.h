#pragma once
// Why the error is what it is (docs/commands.md, "The error taken apart" under bench). For an error_measure whose source
// comes from a screen-space pass (ssgi) and whose reference is a truth layer of the capture, bench
// measures a ladder of images between the two, each closer to the truth than the one before:
//   result → the same chain converged (the tracer at many rays, averaged over Unreal's 8 frame
//   seeds: what is left is the algorithm, not its noise) → framepass's screen_space_oracle (the
//   best any screen-space method does with this depth and colour) → the one-bounce truth (what the
//   screen cannot see) → the full truth (what bounced more than once).
// For a ray-traced GI pass (PassRoles::bouncesParam) the ladder is its own:
//   result → converged (many paths) → every bounce (the paths' bounce count raised) → the truth
//   (what is left is the light the pass leaves out: emitters its rays see, the sky on the first
//   ray).
// The ladder stops at the error_measure's reference; the maths is decomposeError's.
#include "app/BenchResult.h"
#include "app/FrameDriver.h"
#include "app/RunSetup.h"

#include <map>
#include <set>
#include <string>
#include <vector>

namespace fp::app {

/// The most rays per pixel the breakdown's oracle and converged tracer are asked for.
inline constexpr int kMaxBreakdownRays = 1024;

/// An error_measure that can be taken apart, and the rungs between its source and reference.
struct DecompositionTarget {
    std::string errorNode, source, reference;  //!< the error_measure and its two inputs' keys
    std::string tracer;      //!< the screen-space pass upstream of the source
    std::string tracerRays;  //!< its rays-per-pixel parameter (PassRoles::raysParam)
    std::string tracerBounces;  //!< a ray-traced tracer's bounce parameter ("" = screen-space)
    std::string oracleType, oracleRays;  //!< the oracle's pass type and its rays parameter
    std::string oraclePort;  //!< the oracle's output for the same quantity (PassRoles::oracleFor)
    std::vector<std::string> truths;  //!< capture:Truth.* rungs after the oracle, ending at reference
    std::string depth;       //!< the error_measure's depth input ("" = none): sky is left out
    float skyDistance = 0;   //!< its skyDistance parameter
};

/// What an error_measure step measured on a frame (its figures, source and reference keys), as
/// bench and run hand it to the decomposition.
ErrorNodeResult errorNodeResult(const PlanStep& step, const PassReport& report);

/// The error measures of `plan` that can be taken apart: source downstream of a screen-space
/// tracer, reference a truth layer of the capture that the oracle estimates (PassRoles).
/// `available`: the capture's buffers.
std::vector<DecompositionTarget> decompositionTargets(const Plan& plan,
                                                      const std::set<std::string>& available);

/// Runs the extra chains a decomposition needs on bench's capture: the oracle once, the converged
/// chain once per setting (every source it feeds at once).
class ErrorBreakdown {
public:
    /// `rays`: the oracle's rays and the converged tracer's rays per frame seed; `frame`: the
    /// frame whose error is taken apart, its capture read through `frames` (the driver that ran
    /// it, which keeps it read).
    ErrorBreakdown(const RunSetup& probe, FrameDriver& frames,
                   std::vector<DecompositionTarget> targets, int rays, int frame);

    const std::vector<DecompositionTarget>& targets() const { return mTargets; }
    /// Called after each pass of the chains it runs; it may throw (fp::Cancelled) to stop the
    /// breakdown there (the workbench's, when a newer change or a cancel request comes).
    ProgressFn onPass;
    /// Adds the decomposition to every error of `errors` that has a target. `options`: the
    /// setting's --cvar and --set (its dumps are not used); `kept`: the images the run kept of
    /// the frame (the error sources among them; in a sequence, made with history); `label`: the
    /// setting, for the log.
    void decompose(const SetupOptions& options, const std::map<std::string, Image>& kept,
                   const std::string& label, std::vector<ErrorNodeResult>& errors);

    /// Frame seeds the converged chain is averaged over: every value of Unreal's frame index mod 8.
    static constexpr int kFrameSeeds = 8;
    /// The bounce count of a ray-traced ladder's "every bounce" rung: at the Cornell box's albedo
    /// the light after the eighth bounce is −0.0003 of its full GI (algorithms §12.2).
    static constexpr int kAllBounces = 8;

private:
    const Image& oracle(const std::string& port);
    /// The oracle's noise of `port` (after oracle(port)); 0 with one ray (not measured).
    double oracleNoise(const std::string& port) const;
    /// A source averaged over the frame seeds, and the standard error of that mean: the RMSE
    /// over every pixel and channel of sqrt(the seeds' variance / kFrameSeeds).
    struct Converged {
        Image mean;
        double noiseRmse = 0;
    };
    /// The chain with `tracerRays` ("pass.param") at mRays rays, each of `sources` averaged over
    /// the frame seeds.
    /// A ray-traced tracer takes mRays / kFrameSeeds paths per seed (mRays in all); `extraSets`
    /// change the chain further.
    std::map<std::string, Converged> converged(const SetupOptions& options,
                                           const std::string& tracerRays,
                                           int raysPerSeed,
                                           const Settings& extraSets,
                                           const std::vector<std::string>& sources);

    const RunSetup& mProbe;
    std::vector<DecompositionTarget> mTargets;
    int mRays;
    int mFrame;
    FrameDriver& mFrames;
    std::map<std::string, Image> mOracle;  //!< oracle port → image, made on first use
    /// Oracle port → the standard error of that image (RMSE over every value): the oracle is
    /// traced as two halves of its rays with two seeds, whose difference measures it.
    std::map<std::string, double> mOracleNoise;
};

}  // namespace fp::app
