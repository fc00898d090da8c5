// framepass tune: the cheapest setting of a chain whose error meets a target. It benches a grid
// (the --sweep axes, or by default every small-domain cvar of the passes the measured result
// depends on), then refines along the Pareto front: where the cheapest setting that meets the
// target and the next faster one on the front differ in one integer axis with values between
// them, it bisects that axis. It prints the choice as an Unreal [SystemSettings] snippet and as
// JSON; when nothing meets the target it takes the most accurate setting's error apart to say
// what stands in the way.
#include "cli/BenchSweep.h"
#include "cli/Commands.h"
#include "cli/Invocation.h"
#include "io/ConfigLoader.h"
#include "passes/core/CvarTable.h"
#include "passes/core/Error.h"
#include "passes/core/PassRegistry.h"
#include "passes/core/Suggest.h"

#include <fmt/ranges.h>

#include <cmath>
#include <iostream>
#include <optional>
#include <set>

namespace fp::cli {

namespace {

struct TuneOptions {
    BenchOptions bench;
    std::string target;
    int refine = 4;
};

struct Target {
    std::string error;           //!< an error_measure pass
    std::string metric = "rmse";  //!< one of its figures
    double max = 0;
};

// The figures a target may bound: those where smaller is better.
const std::vector<std::string> kTargetMetrics = {"rmse", "relMse", "smape", "mae", "maxError",
                                                 "overTolerance"};

Target parseTarget(const std::string& text) {
    const auto le = text.find("<=");
    if (le == std::string::npos || le == 0)
        throw UsageError(fmt::format(
            "--target {}: expected ERROR_PASS<=VALUE or ERROR_PASS.METRIC<=VALUE", text));
    Target t;
    t.error = text.substr(0, le);
    if (const auto dot = t.error.find('.'); dot != std::string::npos) {
        t.metric = t.error.substr(dot + 1);
        t.error = t.error.substr(0, dot);
        if (std::find(kTargetMetrics.begin(), kTargetMetrics.end(), t.metric) ==
            kTargetMetrics.end())
            throw UsageError(fmt::format("--target {}: '{}' is not a metric a target can bound "
                                         "({}){}",
                                         text, t.metric, fmt::join(kTargetMetrics, ", "),
                                         didYouMean(t.metric, kTargetMetrics)));
    }
    try {
        std::size_t end = 0;
        const std::string value = text.substr(le + 2);
        t.max = std::stod(value, &end);
        if (end != value.size() || !std::isfinite(t.max) || t.max < 0)
            throw std::invalid_argument("");
    } catch (const std::exception&) {
        throw UsageError(fmt::format("--target {}: the bound is a number ≥ 0", text));
    }
    return t;
}

// The target's error_measure in the config, or a usage error naming those it has.
const NodeDesc& targetNode(const io::RunConfig& config, const Target& t) {
    std::vector<std::string> names;
    for (const auto& n : config.graph.nodes) {
        if (n.type != kErrorPassType)
            continue;
        if (n.name == t.error)
            return n;
        names.push_back(n.name);
    }
    throw UsageError(fmt::format("--target: {} has no error_measure pass '{}'{}", config.path,
                                 t.error,
                                 names.empty() ? std::string(" (it has none)")
                                               : didYouMean(t.error, names)));
}

// The parameter a sweep axis sets (a cvar, or PASS.PARAM), as the probe's chain resolves it.
std::optional<ParamInfo> sweptParam(const Bencher& bencher, const std::string& name) {
    const Plan& plan = bencher.probe().plan();
    const CvarTable cvars(builtinPasses());
    for (const PlanStep& step : plan.steps) {
        const PassType* type = builtinPasses().find(step.type);
        if (!type) continue;
        for (const ParamInfo& p : type->params) {
            const bool byCvar =
                std::find(p.cvars.begin(), p.cvars.end(), cvars.spelling(name)) != p.cvars.end();
            if (byCvar || name == step.name + "." + p.name) return p;
        }
    }
    return std::nullopt;
}

// A parameter that acts only across frames does nothing on one frame: every value gives the
// same pixels, and its timings differ only by noise. Said once, the axis dropped.
bool actsOnThisBench(const Bencher& bencher, const std::string& name) {
    if (bencher.probe().frames().size() > 1) return true;
    const auto p = sweptParam(bencher, name);
    if (!p || !p->needsHistory) return true;
    logInfo(fmt::format("tune: {} is not searched: it acts only across frames, and this bench "
                        "runs one frame (give --frames for a sequence)",
                        name));
    return false;
}

// Every small-domain cvar (a bool, or an int range of at most 8 values) of the passes the
// target's source depends on, one axis per cvar.
std::vector<std::string> defaultSweeps(const Bencher& bencher, const Target& t) {
    SessionOptions options = bencher.options().session;
    options.dumps = {t.error + ".heat"};
    const RunSession session(bencher.probe(), options);
    const Plan& plan = session.plan();
    std::vector<std::string> sweeps;
    std::set<std::string> seenCvars;
    for (const PlanStep& step : plan.steps) {
        const PassType* type = builtinPasses().find(step.type);
        if (!type || step.type == kErrorPassType)
            continue;
        for (const ParamInfo& p : type->params) {
            if (p.cvars.empty() || seenCvars.count(p.cvars.front()))
                continue;
            std::string values;
            if (p.type == "bool")
                values = "0,1";
            else if (p.type == "int" && p.min && p.max && *p.max - *p.min <= 7)
                values = fmt::format("{}..{}", int(*p.min), int(*p.max));
            else
                continue;
            for (const auto& c : p.cvars)
                seenCvars.insert(c);
            if (actsOnThisBench(bencher, p.cvars.front()))
                sweeps.push_back(p.cvars.front() + "=" + values);
        }
    }
    return sweeps;
}

struct Tried {
    BenchSetting setting;
    SweepPoint point;
    double value = 0;  //!< the target's metric
    bool refined = false;
};

// A setting's cost.
double frameMs(const Tried& t) { return t.setting.chainSeconds() * 1e3; }

// How far apart two measurements of one setting may lie: the spread of its runs, and with one
// run (no spread of its own) a tenth of its time.
double noiseMs(const Tried& t) {
    const double spread = (t.setting.frame.max - t.setting.frame.min) * 1e3;
    return spread > 0 ? spread : 0.1 * frameMs(t);
}

// How many times tied settings are measured again before they are called equal.
constexpr int kTieRounds = 2;

// The work a chain does (rays, samples, texels… each pass's throughput counter, summed): what
// separates settings whose times cannot.
double chainWork(const BenchSetting& s) {
    double work = 0;
    for (const auto& p : s.passes)
        if (p.type != kErrorPassType && p.type != kBareLoopType) work += double(p.work);
    return work;
}

double metricOf(const BenchSetting& s, const Target& t) {
    for (const auto& e : s.errors)
        if (e.name == t.error) {
            if (auto it = e.metrics.find(t.metric); it != e.metrics.end())
                return it->second;
        }
    throw Error(fmt::format("{} did not report {}", t.error, t.metric));
}

// A sweep value as --set and --cvar read it, when that is an integer.
std::optional<int> integerValue(const std::string& v) {
    const nlohmann::json j = io::parseCliValue(v);
    return j.is_number_integer() ? std::optional<int>(j.get<int>()) : std::nullopt;
}

// The one axis where `a` and `b` differ, when it is the only one and both values are integers.
std::optional<std::size_t> singleIntegerAxis(const SweepPoint& a, const SweepPoint& b) {
    std::optional<std::size_t> axis;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].second == b[i].second)
            continue;
        if (axis || !integerValue(a[i].second) || !integerValue(b[i].second))
            return std::nullopt;
        axis = i;
    }
    return axis;
}

std::string systemSettings(const SweepPoint& point) {
    std::string s = "[SystemSettings]\n";
    for (const auto& [name, value] : point)
        if (name.rfind("r.", 0) == 0)
            s += name + "=" + value + "\n";
    return s;
}

nlohmann::json pointJson(const SweepPoint& point) {
    nlohmann::json cvars = nlohmann::json::object(), params = nlohmann::json::object();
    for (const auto& [name, value] : point)
        (name.rfind("r.", 0) == 0 ? cvars : params)[name] = io::parseCliValue(value);
    return {{"cvars", cvars}, {"params", params}};
}

}  // namespace

Command addTuneCommand(CLI::App& app) {
    auto opt = std::make_shared<TuneOptions>();
    CLI::App* sub = app.add_subcommand(
        "tune",
        "find the cheapest setting whose error meets a target: a grid, then refined along the "
        "Pareto front; prints it as an Unreal [SystemSettings] snippet");
    opt->bench.session.addTo(*sub);
    sub->add_option("--target", opt->target,
                    "ERROR_PASS<=VALUE (its RMSE) or ERROR_PASS.METRIC<=VALUE (rmse, relMse, "
                    "smape, mae, maxError, overTolerance)")
        ->required();
    sub->add_option("--sweep", opt->bench.sweeps,
                    "the grid, as bench's --sweep (default: every cvar of the measured chain "
                    "that is a switch or an integer of at most 8 values)");
    sub->add_option("--refine", opt->refine,
                    "settings at most to try between grid values along the Pareto front "
                    "(default 4)")
        ->check(CLI::Range(0, 100));
    opt->bench.runs = 3;  // tune's default: a grid of settings, each timed
    opt->bench.addTimingOptions(*sub);
    addDecomposeRaysOption(*sub, opt->bench.decomposeRays,
                           "rays of the error decomposition shown when nothing meets the target "
                           "(default 256; 0: none)");
    sub->add_flag("--json", opt->bench.json, "print the result as JSON");

    return [opt]() {
        const Target target = parseTarget(opt->target);
        Bencher bencher(opt->bench);
        targetNode(bencher.probe().config(), target);
        std::vector<std::string> sweeps;
        for (const auto& s : opt->bench.sweeps)
            if (actsOnThisBench(bencher, s.substr(0, s.find('='))))
                sweeps.push_back(s);
        if (opt->bench.sweeps.empty()) {
            sweeps = defaultSweeps(bencher, target);
            if (sweeps.empty())
                throw UsageError(fmt::format(
                    "tune: no cvar of the chain behind {} has a small domain to search; give "
                    "--sweep",
                    target.error));
            logInfo(fmt::format("tune: searching {}", fmt::join(sweeps, " × ")));
        }
        const std::vector<SweepPoint> grid = sweepGrid(sweeps);
        const int perSetting = opt->bench.warmup + opt->bench.runs;
        bencher.expectRuns(int(grid.size() + std::size_t(opt->refine)) * perSetting);

        std::vector<Tried> tried;
        auto measure = [&](const SweepPoint& p, bool refined) -> const Tried& {
            for (const Tried& t : tried)
                if (t.point == p)
                    return t;
            Tried t{bencher.measure(p, false), p, 0, refined};
            t.value = metricOf(t.setting, target);
            tried.push_back(std::move(t));
            return tried.back();
        };
        for (const auto& p : grid)
            measure(p, false);

        // Refine: bisect the one integer axis between the cheapest setting that meets the target
        // and the next faster setting of the Pareto front, while values lie between them.
        auto cheapestMeeting = [&]() -> const Tried* {
            const Tried* best = nullptr;
            for (const Tried& t : tried)
                if (t.value <= target.max && (!best || frameMs(t) < frameMs(*best)))
                    best = &t;
            return best;
        };
        for (int round = 0; round < opt->refine; ++round) {
            const Tried* meets = cheapestMeeting();
            if (!meets)
                break;
            // The fastest setting that is cheaper and more accurate than every other cheaper one:
            // the front's point just below the choice.
            const Tried* below = nullptr;
            for (const Tried& t : tried) {
                if (frameMs(t) >= frameMs(*meets))
                    continue;
                if (!below || t.value < below->value)
                    below = &t;
            }
            if (!below)
                break;
            const auto axis = singleIntegerAxis(meets->point, below->point);
            if (!axis)
                break;
            const int a = *integerValue(below->point[*axis].second);
            const int b = *integerValue(meets->point[*axis].second);
            if (std::abs(a - b) < 2)
                break;
            // Midpoint; geometric where the values span a factor of 4 or more (ray counts).
            const int lo = std::min(a, b), hi = std::max(a, b);
            int mid = lo > 0 && hi >= 4 * lo ? int(std::lround(std::sqrt(double(lo) * hi)))
                                             : (lo + hi) / 2;
            mid = std::clamp(mid, lo + 1, hi - 1);
            SweepPoint p = meets->point;
            p[*axis].second = std::to_string(mid);
            const std::size_t before = tried.size();
            measure(p, true);
            if (tried.size() == before)
                break;
        }

        // Times closer than their noise do not order two settings: measure both again, and
        // if they stay that close, call them equal and take the one that does less work.
        const Tried* choice = cheapestMeeting();
        std::string tieNote;
        for (int round = 0; choice && round <= kTieRounds; ++round) {
            std::vector<Tried*> ties;
            for (Tried& t : tried)
                if (&t != choice && t.value <= target.max &&
                    std::fabs(frameMs(t) - frameMs(*choice)) <= noiseMs(t) + noiseMs(*choice))
                    ties.push_back(&t);
            if (ties.empty()) break;
            if (round == kTieRounds) {
                const Tried* least = choice;
                for (const Tried* t : ties)
                    if (chainWork(t->setting) < chainWork(least->setting)) least = t;
                tieNote = fmt::format(
                    "{} setting(s) within the timing noise of {} after {} more measurement(s): "
                    "taken as equal, the one with the least work chosen",
                    ties.size(), choice->setting.label, kTieRounds);
                choice = least;
                break;
            }
            ties.push_back(const_cast<Tried*>(choice));
            for (Tried* t : ties) {
                t->setting = bencher.measure(t->point, false);
                t->value = metricOf(t->setting, target);
            }
            choice = cheapestMeeting();
        }
        const Tried* mostAccurate = &tried.front();
        for (const Tried& t : tried)
            if (t.value < mostAccurate->value)
                mostAccurate = &t;
        std::optional<ErrorDecompositionResult> inTheWay;
        if (!choice && opt->bench.decomposeRays > 0) {
            BenchSetting again = bencher.measure(mostAccurate->point, true);
            for (const auto& e : again.errors)
                if (e.name == target.error && e.decomposition)
                    inTheWay = e.decomposition;
        }

        const std::string bound =
            fmt::format("{} {} ≤ {:g}", target.error, target.metric, target.max);
        if (opt->bench.json) {
            nlohmann::json j = {{"config", opt->bench.session.config},
                                {"target",
                                 {{"error", target.error},
                                  {"metric", target.metric},
                                  {"max", target.max}}},
                                {"met", choice != nullptr}};
            j["settings"] = nlohmann::json::array();
            for (const Tried& t : tried)
                j["settings"].push_back({{"label", t.setting.label},
                                         {"setting", pointJson(t.point)},
                                         {"frameMs", frameMs(t)},
                                         {"value", t.value},
                                         {"meets", t.value <= target.max},
                                         {"refined", t.refined}});
            if (choice) {
                j["choice"] = {{"label", choice->setting.label},
                               {"setting", pointJson(choice->point)},
                               {"frameMs", frameMs(*choice)},
                               {"value", choice->value}};
                j["systemSettings"] = systemSettings(choice->point);
                if (!tieNote.empty()) j["tie"] = tieNote;
            } else {
                j["mostAccurate"] = {{"label", mostAccurate->setting.label},
                                     {"setting", pointJson(mostAccurate->point)},
                                     {"frameMs", frameMs(*mostAccurate)},
                                     {"value", mostAccurate->value}};
                if (inTheWay)
                    j["inTheWay"] = inTheWay->toJson();
            }
            std::cout << j.dump(2) << "\n";
        } else {
            std::size_t refined = 0;
            for (const Tried& t : tried)
                refined += t.refined ? 1 : 0;
            std::cout << fmt::format("tune {}: {} over {} settings ({} on the grid, {} refined)\n",
                                     opt->bench.session.config, bound, tried.size(),
                                     tried.size() - refined, refined);
            for (const Tried& t : tried)
                std::cout << fmt::format("  {:<48} {:>9.2f} ms  {} {:.5g}{}{}\n", t.setting.label,
                                         frameMs(t), target.metric, t.value,
                                         t.value <= target.max ? "  meets" : "",
                                         t.refined ? "  (refined)" : "");
            if (!tieNote.empty()) std::cout << tieNote << "\n";
            if (choice) {
                std::cout << fmt::format("cheapest setting that meets {}: {} ({:.2f} ms, {} "
                                         "{:.5g})\n",
                                         bound, choice->setting.label, frameMs(*choice),
                                         target.metric, choice->value);
                std::cout << systemSettings(choice->point);
                for (const auto& [name, value] : choice->point)
                    if (name.rfind("r.", 0) != 0)
                        std::cout << fmt::format("; framepass only (no Unreal cvar): --set {}={}\n",
                                                 name, value);
            } else {
                std::cout << fmt::format("no setting meets {}: the most accurate, {}, has {} "
                                         "{:.5g} ({:.2f} ms)\n",
                                         bound, mostAccurate->setting.label, target.metric,
                                         mostAccurate->value, frameMs(*mostAccurate));
                if (inTheWay)
                    std::cout << "what stands in the way:\n" << decompositionText(*inTheWay);
            }
        }
        return choice ? 0 : 1;
    };
}

}  // namespace fp::cli
