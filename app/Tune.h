#pragma once
// tune: the cheapest setting of a chain whose error meets a target (a grid benched, then refined
// along the Pareto front; app/Tune.cpp says how). The CLI's `tune` prints what this returns.
#include "app/BenchSweep.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace fp::app {

struct TuneOptions {
    BenchOptions bench;  //!< the config, its settings, runs; the sweeps (empty: a default grid)
    /// ERROR_PASS<=VALUE or ERROR_PASS.METRIC<=VALUE; with a budget the bound may be left out
    /// (ERROR_PASS or ERROR_PASS.METRIC: the measure whose error is made least).
    std::string target;
    int refine = 4;      //!< settings at most to try between grid values
    /// "4ms" (or "4", milliseconds, or "0.004s"): instead of the cheapest setting that meets the
    /// target, the most accurate whose method (the passes the target's source depends on) takes
    /// at most this a frame. "" = none.
    std::string budget;
};

struct TuneTarget {
    std::string error;            //!< an error measure of the config
    std::string metric = "rmse";  //!< one of its figures
    double max = 0;               //!< +inf: no bound (a budget's search)
};

struct TunedSetting {
    BenchSetting setting;
    SweepPoint point;
    double value = 0;  //!< the target's metric
    bool refined = false;
    /// The time of the target's method: the passes its source depends on (ErrorNodeResult).
    double methodMs = 0;
    /// The setting's cost: the chain's time per frame.
    double frameMs() const { return setting.chainSeconds() * 1e3; }
};

struct TuneResult {
    TuneTarget target;
    std::vector<TunedSetting> tried;  //!< in the order measured
    /// The cheapest that meets the target; with a budget, the most accurate within it.
    std::optional<std::size_t> choice;
    std::optional<double> budgetMs;  //!< the budget searched within
    std::size_t mostAccurate = 0;
    std::string tieNote;  //!< settings whose times could not be told apart, and how one was chosen
    /// Nothing met the target: the most accurate setting's error taken apart.
    std::optional<ErrorDecompositionResult> inTheWay;

    /// "ssgi_error rmse ≤ 0.05", or with a budget "ssgi_error rmse, its method within 4 ms"
    std::string bound() const;
    /// What `tune --json` prints.
    nlohmann::json toJson(const std::string& config) const;
    /// The axes that rebind an input (an error measure's source, say), not a parameter.
    std::set<std::string> inputAxes;
    /// A point as {"cvars": {...}, "params": {...}, "inputs": {...}}.
    nlohmann::json pointJson(const SweepPoint& point) const;
};

/// Runs the search; throws fp::UsageError for a bad target or when there is nothing to search.
TuneResult tune(const TuneOptions& options);

/// The point's cvars as an Unreal .ini section.
std::string systemSettings(const SweepPoint& point);
/// The same for a tuned setting; a cvar that no pass of the setting's chain reads
/// (its method's chain has none of its passes) is a comment line saying so.
std::string systemSettings(const TunedSetting& setting);

/// Where a setting's point sets more than cvars (a parameter, or an error's source picking a
/// method): the Unreal setting that turns on each method the setting runs, as .ini comment lines
/// ("; the method: r.RayTracing.GlobalIllumination=1"), or that a method is framepass's own.
std::string methodSettings(const TunedSetting& setting);

}  // namespace fp::app
