#include "app/ErrorBreakdown.h"

#include "app/Invocation.h"
#include "screenspace/GBuffer.h"
#include "foundation/Error.h"
#include "metrics/ErrorDecomposition.h"
#include "metrics/ErrorMetrics.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace fp::app {

namespace {

// The oracle runs in a chain of its own, so its name cannot clash with the config's passes.
constexpr const char* kOracleNode = "decomposition_oracle";

// The truth of light that bounced once, and of all of it: a rung between the two says how much
// of the error is multi-bounce light.
constexpr const char* kOneBounce = "Truth.DiffuseIndirectOneBounce";
constexpr const char* kFull = "Truth.DiffuseIndirectFull";

// The pass type that declares itself a screen-space oracle (PassRoles::oracleFor), or null.
const PassType* oracleType() {
    for (const PassType& t : builtinPasses().types())
        if (!t.roles.oracleFor.empty())
            return &t;
    return nullptr;
}

/// What one step of the ladder is, and what would reduce it.
struct StepKind {
    const char* name;    //!< in tables and JSON
    const char* phrase;  //!< in the sentence: "Most of the error is <phrase>"
    const char* remedy;
};

// The steps in ladder order: result → converged → oracle → one-bounce truth → full truth.
constexpr StepKind kSteps[] = {
    {"noise", "noise",
     "more rays (r.SSGI.Quality) or more frames of the denoiser's temporal accumulation reduce "
     "it"},
    {"approximation", "Unreal's approximation",
     "it is the algorithm itself (the HZB mip schedule, the Karis weighting of bright hits, the "
     "reduced colour's coarse mips); r.SSGI.Quality changes the schedule, but no setting reaches "
     "the exact screen-space march"},
    {"screen-space limit", "the screen-space limit",
     "it is what the screen does not show (surfaces off screen or hidden, and light shapes seen "
     "on screen that the truth counts as lights); no screen-space setting reduces it, a method "
     "that sees the whole scene (ray-traced GI) would"},
    {"multi-bounce", "multi-bounce light",
     "a one-bounce gather misses light that bounced more than once; measure against "
     "Truth.DiffuseIndirectOneBounce to judge the pass on what it can see"},
};

// The ray-traced ladder's steps: result → converged → every bounce → full truth.
constexpr StepKind kRayTracedSteps[] = {
    {"noise", "noise",
     "more paths a pixel (the pass's samplesPerPixel), the denoiser or more frames of its "
     "temporal accumulation reduce it"},
    {"bounces not traced", "the light of the bounces not traced",
     "the paths stop after maxBounces (r.RayTracing.GlobalIllumination.MaxBounces); more bounces "
     "add it, each about one more ray and its light samples a path"},
    {"left out", "light the pass leaves out",
     "Unreal's ray-traced GI shades its hits diffuse only (a mirror or glossy surface a GI ray "
     "sees reflects nothing), adds no emission at them (an emitter lights nothing) and no sky on "
     "its first ray (the sky light's diffuse term is another pass's); no setting of the pass adds "
     "it (where a denoiser follows the pass, its blur is here too)"},
};

// The nearest tracer (a pass that declares its rays parameter, not the oracle)
// upstream of step `from`, itself included; null when there is none.
const PlanStep* upstreamTracer(const Plan& plan, int from) {
    std::vector<int> queue = {from};
    std::set<int> seen;
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const int i = queue[q];
        if (i < 0 || !seen.insert(i).second)
            continue;
        const PlanStep& step = plan.steps[std::size_t(i)];
        if (!step.io.roles.raysParam.empty() && step.io.roles.oracleFor.empty())
            return &step;
        for (const auto& [port, ref] : step.inputs)
            if (!ref.fromCapture)
                queue.push_back(ref.step);
    }
    return nullptr;
}

// A copy of a config whose chain writes no files: only what is dumped is run.
io::RunConfig chainWithoutOutputs(const io::RunConfig& config) {
    io::RunConfig c = config;
    c.graph.outputs.clear();
    for (auto& t : c.graph.lightTemplates)
        t.outputs.clear();
    return c;
}

// A point-upsampled image is read at half resolution by decomposeError instead.
bool isHalf(const Image& image, const Image& reference) {
    return isHalfResolution({image.width(), image.height()}, {reference.width(), reference.height()});
}

}  // namespace

std::vector<DecompositionTarget> decompositionTargets(const Plan& plan,
                                                      const std::set<std::string>& available) {
    std::vector<DecompositionTarget> targets;
    const PassType* oracle = oracleType();
    for (const PlanStep& step : plan.steps) {
        if (!step.io.roles.measuresError)
            continue;
        const SourceRef& source = step.inputs.at("source");
        const SourceRef& reference = step.inputs.at("reference");
        if (source.fromCapture || !reference.fromCapture)
            continue;
        const PlanStep* tracer = upstreamTracer(plan, source.step);
        if (!tracer)
            continue;
        DecompositionTarget t;
        t.errorNode = step.name;
        t.source = source.key;
        t.reference = reference.key;
        t.tracer = tracer->name;
        t.tracerRays = tracer->io.roles.raysParam;
        t.tracerBounces = tracer->io.roles.bouncesParam;
        if (!t.tracerBounces.empty()) {
            // A ray-traced GI pass: its own ladder, to the full truth only.
            if (reference.buffer != kFull)
                continue;
        } else {
            if (!oracle)
                continue;
            const auto port = oracle->roles.oracleFor.find(reference.buffer);
            if (port == oracle->roles.oracleFor.end())
                continue;
            t.oracleType = oracle->id;
            t.oracleRays = oracle->roles.raysParam;
            t.oraclePort = port->second;
            // Against the full truth, the one-bounce truth is a rung of its own when the oracle
            // estimates it too.
            if (reference.buffer == kFull && oracle->roles.oracleFor.count(kOneBounce))
                t.truths.push_back(std::string("capture:") + kOneBounce);
        }
        t.truths.push_back(reference.key);
        if (!std::all_of(t.truths.begin(), t.truths.end(), [&](const std::string& k) {
                return available.count(k.substr(8)) > 0;
            }))
            continue;
        if (auto it = step.inputs.find(gbuffer::kDepth); it != step.inputs.end())
            t.depth = it->second.key;
        t.skyDistance = step.params.value("skyDistance", 0.0f);
        targets.push_back(std::move(t));
    }
    return targets;
}

ErrorNodeResult errorNodeResult(const PlanStep& step, const PassReport& report) {
    ErrorNodeResult e;
    e.name = step.name;
    e.metrics = report.metrics;
    e.source = step.inputs.at("source").key;
    e.reference = step.inputs.at("reference").key;
    return e;
}

ErrorBreakdown::ErrorBreakdown(const RunSetup& probe, FrameDriver& frames,
                               std::vector<DecompositionTarget> targets, int rays, int frame)
    : mProbe(probe), mTargets(std::move(targets)), mRays(rays), mFrame(frame), mFrames(frames) {}

const Image& ErrorBreakdown::oracle(const std::string& port) {
    if (auto it = mOracle.find(port); it != mOracle.end())
        return it->second;
    // Every port the screen-space targets read, traced together once.
    io::RunConfig config = chainWithoutOutputs(mProbe.config());
    const DecompositionTarget& first = *std::find_if(
        mTargets.begin(), mTargets.end(), [](const auto& t) { return !t.oracleType.empty(); });
    config.graph.nodes = {
        {kOracleNode, first.oracleType, {{first.oracleRays, mRays}}, {}, "/decomposition"}};
    config.graph.lightTemplates.clear();
    SetupOptions options;
    options.config = mProbe.config().path;
    options.frames = std::to_string(mFrame);
    for (const auto& t : mTargets) {
        if (t.oracleType.empty())
            continue;
        const std::string key = std::string(kOracleNode) + "." + t.oraclePort;
        if (std::find(options.dumps.begin(), options.dumps.end(), key) == options.dumps.end())
            options.dumps.push_back(key);
    }
    logInfo(fmt::format("error decomposition: {} at {} rays per pixel", first.oracleType, mRays));
    // Two halves of the rays with two seeds, weighted by their rays: the same rays in all as
    // one trace, and their difference measures the result's noise. Of halves A and B (a and b
    // rays), the mean's variance is σ²/mRays for a one-ray variance σ², and A − B's is
    // σ²(1/a + 1/b): the mean's standard error is RMSE(A − B) · sqrt(1 / (mRays (1/a + 1/b))).
    const int halves[2] = {mRays - mRays / 2, mRays / 2};
    std::map<std::string, Image> traced[2];
    for (int h = 0; h < (mRays >= 2 ? 2 : 1); ++h) {
        config.graph.nodes.front().params[first.oracleRays] = halves[h];
        const RunSetup session(mProbe, config, options);
        KeepingSink sink;
        sink.keep = true;
        mFrames.runApart(session.plan(), mFrame, sink, mFrame + h * kFrameSeeds, onPass);
        traced[h] = std::move(sink.images);
    }
    for (const auto& t : mTargets) {
        if (t.oracleType.empty())
            continue;
        const std::string key = std::string(kOracleNode) + "." + t.oraclePort;
        Image mean = traced[0].at(key);
        double squared = 0;
        std::size_t values = 0;
        if (mRays >= 2) {
            const Image& other = traced[1].at(key);
            const float wa = float(halves[0]) / float(mRays), wb = float(halves[1]) / float(mRays);
            for (int c = 0; c < mean.channelCount(); ++c)
                for (int y = 0; y < mean.height(); ++y)
                    for (int x = 0; x < mean.width(); ++x, ++values) {
                        const float a = mean.plane(c).at(x, y), b = other.plane(c).at(x, y);
                        squared += double(a - b) * double(a - b);
                        mean.plane(c).at(x, y) = wa * a + wb * b;
                    }
            const double scale = 1.0 / (double(mRays) * (1.0 / halves[0] + 1.0 / halves[1]));
            mOracleNoise[t.oraclePort] = std::sqrt(squared / double(values) * scale);
        }
        mOracle[t.oraclePort] = std::move(mean);
    }
    return mOracle.at(port);
}

double ErrorBreakdown::oracleNoise(const std::string& port) const {
    const auto it = mOracleNoise.find(port);
    return it == mOracleNoise.end() ? 0.0 : it->second;
}

std::map<std::string, ErrorBreakdown::Converged> ErrorBreakdown::converged(
    const SetupOptions& setting,
                                                        const std::string& tracerRays,
                                                        int raysPerSeed,
                                                        const Settings& extraSets,
                                                        const std::vector<std::string>& sources) {
    SetupOptions options = setting;
    options.dumps = sources;
    options.settings.setParam(tracerRays, raysPerSeed);
    options.settings.merge(extraSets);
    const RunSetup session(mProbe, chainWithoutOutputs(mProbe.config()), options);
    std::map<std::string, Image> sum;
    std::map<std::string, std::vector<double>> squares;  // per value, the sum of its squares
    for (int k = 0; k < kFrameSeeds; ++k) {
        KeepingSink sink;
        sink.keep = true;
        mFrames.runApart(session.plan(), mFrame, sink, mFrame + k, onPass);
        for (const auto& source : sources) {
            const Image& img = sink.images.at(source);
            if (k == 0) {
                sum[source] = img;
                squares[source].assign(std::size_t(img.channelCount()) * img.width() * img.height(), 0.0);
            }
            Image& s = sum.at(source);
            std::vector<double>& sq = squares.at(source);
            std::size_t i = 0;
            for (int c = 0; c < s.channelCount(); ++c)
                for (int y = 0; y < s.height(); ++y)
                    for (int x = 0; x < s.width(); ++x, ++i) {
                        const double v = img.plane(c).at(x, y);
                        sq[i] += v * v;
                        if (k > 0) s.plane(c).at(x, y) += img.plane(c).at(x, y);
                    }
        }
    }
    std::map<std::string, Converged> out;
    for (auto& [source, s] : sum) {
        // The seeds' unbiased variance over kFrameSeeds of the mean: its squared standard error.
        const std::vector<double>& sq = squares.at(source);
        double meanSquaredError = 0;
        std::size_t i = 0;
        for (int c = 0; c < s.channelCount(); ++c)
            for (int y = 0; y < s.height(); ++y)
                for (int x = 0; x < s.width(); ++x, ++i) {
                    const double total = s.plane(c).at(x, y), n = kFrameSeeds;
                    const double variance = std::max(0.0, (sq[i] - total * total / n) / (n - 1));
                    meanSquaredError += variance / n;
                    s.plane(c).at(x, y) /= float(kFrameSeeds);
                }
        out[source] = {std::move(s), std::sqrt(meanSquaredError / double(std::max<std::size_t>(i, 1)))};
    }
    return out;
}

void ErrorBreakdown::decompose(const SetupOptions& options,
                                const std::map<std::string, Image>& kept,
                                const std::string& label,
                                std::vector<ErrorNodeResult>& errors) {
    // One converged chain per tracer serves every error whose source it feeds; a ray-traced
    // tracer's "every bounce" rung is a second one.
    struct Tracer {
        std::string rays, bounces;  // "pass.param"
        std::vector<std::string> sources;
    };
    std::map<std::string, Tracer> tracers;
    for (const ErrorNodeResult& e : errors)
        for (const auto& t : mTargets)
            if (t.errorNode == e.name) {
                Tracer& tr = tracers[t.tracer];
                tr.rays = t.tracer + "." + t.tracerRays;
                tr.bounces = t.tracerBounces.empty() ? "" : t.tracer + "." + t.tracerBounces;
                if (std::find(tr.sources.begin(), tr.sources.end(), t.source) == tr.sources.end())
                    tr.sources.push_back(t.source);
            }
    std::map<std::string, Converged> convergedBySource, allBouncesBySource;
    // A ray-traced tracer's paths are split over the frame seeds (mRays paths in all, as the
    // screen-space tracer's converged rung averages mRays rays of each seed: its noise is the
    // seed's pattern, not only the ray count).
    const int raysPerSeed = std::max(1, mRays / kFrameSeeds);
    for (const auto& [name, tr] : tracers) {
        const bool rayTraced = !tr.bounces.empty();
        const int rays = rayTraced ? raysPerSeed : mRays;
        logInfo(fmt::format("error decomposition, {}: {} converged ({} at {} rays, {} frame "
                            "seeds)",
                            label, fmt::join(tr.sources, " and "), name, rays, kFrameSeeds));
        convergedBySource.merge(converged(options, tr.rays, rays, {}, tr.sources));
        if (rayTraced) {
            logInfo(fmt::format("error decomposition, {}: {} at {} bounces", label,
                                fmt::join(tr.sources, " and "), kAllBounces));
            Settings allBounces;
            allBounces.setParam(tr.bounces, kAllBounces);
            allBouncesBySource.merge(converged(options, tr.rays, rays, allBounces, tr.sources));
        }
    }
    for (ErrorNodeResult& e : errors) {
        const auto t = std::find_if(mTargets.begin(), mTargets.end(), [&](const auto& t) {
            return t.errorNode == e.name;
        });
        if (t == mTargets.end())
            continue;
        const bool rayTraced = !t->tracerBounces.empty();
        const StepKind* kinds = rayTraced ? kRayTracedSteps : kSteps;
        const Image& conv = convergedBySource.at(t->source).mean;
        // The rungs: this setting's result (its last timed run), converged, then the oracle
        // (screen space) or every bounce (ray traced), then the truths.
        const Image& result = kept.at(t->source);
        const int channels = result.channelCount();
        std::vector<Texture> truths;
        for (const auto& key : t->truths)
            truths.push_back(mFrames.source(mFrame).loadBuffer(key.substr(8), channels));
        const Image& reference = truths.back().image();
        std::vector<LadderRung> ladder = {{&result, isHalf(result, reference)},
                                          {&conv, isHalf(conv, reference)}};
        std::vector<std::string> rungNames = {
            t->source, fmt::format("{} converged ({}.{}={}, {} frame seeds)", t->source, t->tracer,
                                   t->tracerRays, rayTraced ? raysPerSeed : mRays, kFrameSeeds)};
        if (rayTraced) {
            const Image& all = allBouncesBySource.at(t->source).mean;
            ladder.push_back({&all, isHalf(all, reference)});
            rungNames.push_back(fmt::format("{} converged at {}.{}={}", t->source, t->tracer,
                                            t->tracerBounces, kAllBounces));
        } else {
            ladder.push_back({&oracle(t->oraclePort), false});
            rungNames.push_back(fmt::format("{}.{} ({} rays)", t->oracleType, t->oraclePort, mRays));
        }
        for (const Texture& truth : truths)
            ladder.push_back({&truth.image(), false});
        rungNames.insert(rungNames.end(), t->truths.begin(), t->truths.end());
        std::optional<Image> mask;
        if (!t->depth.empty())
            mask = notSkyMask(mFrames.source(mFrame).loadBuffer(t->depth.substr(8), 1).image(),
                              skyDepthFor(t->skyDistance));
        const ErrorDecompositionStats stats = decomposeError(ladder, mask ? &*mask : nullptr);

        ErrorDecompositionResult d;
        d.rmse = stats.rmse;
        d.bias = stats.bias;
        d.convergedNoiseRmse = convergedBySource.at(t->source).noiseRmse;
        if (!rayTraced) d.oracleNoiseRmse = oracleNoise(t->oraclePort);
        std::size_t dominant = 0;
        for (std::size_t k = 0; k < stats.steps.size(); ++k) {
            d.steps.push_back({kinds[k].name, rungNames[k], rungNames[k + 1],
                               stats.steps[k].rmse, stats.steps[k].bias, stats.steps[k].share});
            if (stats.steps[k].share > stats.steps[dominant].share)
                dominant = k;
        }
        // A step with a negative share pulls the result towards the truth, against the others:
        // say so, or a share over 100 % reads like an error in the arithmetic.
        std::string cancels;
        for (std::size_t k = 0; k < stats.steps.size(); ++k)
            if (stats.steps[k].share <= -0.005)  // what prints as 0 % cancels nothing
                cancels += fmt::format("{}{} cancels {:.0f} %", cancels.empty() ? "; " : ", ",
                                       kinds[k].name, -100.0 * stats.steps[k].share);
        d.sentence = fmt::format("Most of the error is {} ({:.0f} % of the squared error{}): {}.",
                                 kinds[dominant].phrase, 100.0 * stats.steps[dominant].share,
                                 cancels, kinds[dominant].remedy);
        // The converged rung and the oracle bound the first steps: their own noise is in those
        // steps' differences. Over a quarter of the dominant step's RMSE (a sixteenth of its
        // squared error), it is no longer small beside what the shares apportion: say so, and
        // what settles it.
        const double noise = std::hypot(d.convergedNoiseRmse, d.oracleNoiseRmse);
        const double dominantRmse = stats.steps[dominant].rmse;
        if (noise > 0.25 * dominantRmse)
            d.sentence += fmt::format(
                " But with {} rays the rungs' own noise (RMSE {:.3g}) is over a quarter of the "
                "dominant step's RMSE ({:.3g}), so the shares of the steps next to them are "
                "partly noise: take it apart with more rays to trust them.",
                mRays, noise, dominantRmse);
        e.decomposition = std::move(d);
    }
}

}  // namespace fp::app
