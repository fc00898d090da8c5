#include "app/BenchResult.h"

#include <fmt/format.h>

#include <algorithm>

namespace fp::app {

TimingStats TimingStats::of(std::vector<double> s) {
    TimingStats t;
    if (s.empty()) return t;
    std::sort(s.begin(), s.end());
    const std::size_t n = s.size();
    t.median = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    t.min = s.front();
    t.max = s.back();
    return t;
}

void BenchResult::markPareto() {
    for (auto& a : settings) {
        a.pareto = a.hasError();
        if (!a.pareto) continue;
        for (const auto& b : settings) {
            if (&a == &b || !b.hasError()) continue;
            const bool noWorse = b.frame.median <= a.frame.median && b.error() <= a.error();
            const bool better = b.frame.median < a.frame.median || b.error() < a.error();
            if (noWorse && better) a.pareto = false;
        }
    }
}

double BenchSetting::chainSeconds() const {
    double seconds = 0;
    for (const auto& p : passes)
        if (!p.measuresError && p.type != kBareLoopType)
            seconds += p.seconds.median;
    return seconds;
}

nlohmann::json ErrorDecompositionResult::toJson() const {
    nlohmann::json j = {{"rmse", rmse}, {"bias", bias}, {"sentence", sentence},
                        {"convergedNoiseRmse", convergedNoiseRmse},
                        {"oracleNoiseRmse", oracleNoiseRmse}};
    j["steps"] = nlohmann::json::array();
    for (const auto& s : steps)
        j["steps"].push_back({{"name", s.name}, {"from", s.from}, {"to", s.to}, {"rmse", s.rmse},
                              {"bias", s.bias}, {"share", s.share}});
    return j;
}

std::string decompositionText(const ErrorDecompositionResult& d) {
    std::string out;
    out += fmt::format("    taken apart (RMSE {:.5g}, bias {:+.5g}):\n", d.rmse, d.bias);
    double biases = 0;
    for (const auto& s : d.steps) {
        out += fmt::format("      {:<19} RMSE {:.5g}  bias {:+.5g}  share {:5.1f} %   {} → {}\n",
                           s.name, s.rmse, s.bias, 100.0 * s.share, s.from, s.to);
        biases += s.bias;
    }
    out += fmt::format("      the step biases add up to {:+.5g} (the total bias {:+.5g}); the "
                       "noise of the converged rung: RMSE {:.3g}, of the oracle: {:.3g}\n",
                       biases, d.bias, d.convergedNoiseRmse, d.oracleNoiseRmse);
    out += "    " + d.sentence + "\n";
    return out;
}

nlohmann::json IncrementalTiming::toJson() const {
    auto stats = [](const TimingStats& t) {
        return nlohmann::json{{"median", t.median}, {"min", t.min}, {"max", t.max}};
    };
    return {{"setting", setting},   {"values", values},     {"frameSeconds", stats(frame)},
            {"rerunSeconds", stats(rerun)}, {"executed", executed}, {"passes", passes}};
}

nlohmann::json BenchResult::toJson() const {
    nlohmann::json j = {{"config", config}, {"capture", capture}, {"frame", frame},
                        {"frames", frames},
                        {"width", extent.width}, {"height", extent.height}, {"runs", runs},
                        {"warmup", warmup}, {"threads", threads}, {"sweeps", sweeps}, {"device", device}};
    j["settings"] = nlohmann::json::array();
    for (const auto& s : settings) {
        nlohmann::json sj = {{"label", s.label},
                             {"frameSeconds",
                              {{"median", s.frame.median}, {"min", s.frame.min}, {"max", s.frame.max}}},
                             {"peakBytes", s.peakBytes},
                             {"peakBytesPerPixel", double(s.peakBytes) / (double(extent.width) * extent.height)}};
        sj["passes"] = nlohmann::json::array();
        for (const auto& p : s.passes) {
            sj["passes"].push_back({{"name", p.name},
                                    {"type", p.type},
                                    {"median", p.seconds.median},
                                    {"min", p.seconds.min},
                                    {"max", p.seconds.max},
                                    {"unit", p.unit},
                                    {"work", p.work},
                                    {"throughput", p.throughput()}});
            if (p.gpuSeconds)
                sj["passes"].back()["gpuSeconds"] = {{"median", p.gpuSeconds->median},
                                                     {"min", p.gpuSeconds->min},
                                                     {"max", p.gpuSeconds->max}};
            if (p.bareSeconds) {
                sj["passes"].back()["bareSeconds"] = *p.bareSeconds;
                sj["passes"].back()["bareRatio"] = p.bareRatio();
            }
        }
        sj["errors"] = nlohmann::json::array();
        for (const auto& e : s.errors) {
            sj["errors"].push_back({{"name", e.name}, {"source", e.source},
                                    {"reference", e.reference}, {"metrics", e.metrics}});
            if (!e.rmseByFrame.empty())
                sj["errors"].back()["rmseByFrame"] = e.rmseByFrame;
            if (e.decomposition)
                sj["errors"].back()["decomposition"] = e.decomposition->toJson();
            if (!e.warnings.empty())
                sj["errors"].back()["warnings"] = e.warnings;
            sj["errors"].back()["methodPasses"] = e.methodPasses;
            sj["errors"].back()["methodSeconds"] = e.methodSeconds;
        }
        if (s.hasError()) sj["pareto"] = s.pareto;
        j["settings"].push_back(sj);
    }
    if (incremental) j["incremental"] = incremental->toJson();
    return j;
}

}  // namespace fp::app
