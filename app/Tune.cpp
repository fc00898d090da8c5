// tune: the cheapest setting of a chain whose error meets a target. It benches a grid
// (the --sweep axes, or by default every small-domain cvar of the passes the measured result
// depends on), then refines along the Pareto front: where the cheapest setting that meets the
// target and the next faster one on the front differ in one integer axis with values between
// them, it bisects that axis. It prints the choice as an Unreal [SystemSettings] snippet and as
// JSON; when nothing meets the target it takes the most accurate setting's error apart to say
// what stands in the way.
#include "app/Tune.h"

#include "app/Settings.h"
#include "app/Invocation.h"
#include "io/ConfigLoader.h"
#include "framework/CvarTable.h"
#include "foundation/Error.h"
#include "framework/PassRegistry.h"
#include "foundation/Suggest.h"

#include <fmt/ranges.h>

#include <cmath>
#include <limits>
#include <optional>
#include <set>

namespace fp::app {

namespace {



// The figures a target may bound: those where smaller is better.
const std::vector<std::string> kTargetMetrics = {"rmse", "relMse", "smape", "mae", "maxError",
                                                 "overTolerance"};

TuneTarget parseTarget(const std::string& text, bool budget) {
    auto le = text.find("<=");
    if (le == 0 || (le == std::string::npos && !budget))
        throw UsageError(fmt::format(
            "--target {}: expected ERROR_PASS<=VALUE or ERROR_PASS.METRIC<=VALUE (with --budget, "
            "ERROR_PASS alone)",
            text));
    TuneTarget t;
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
    if (le == std::string::npos) {
        t.max = std::numeric_limits<double>::infinity();
        return t;
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

// --budget's text as milliseconds: "4ms", "4" (milliseconds) or "0.004s".
double parseBudgetMs(const std::string& text) {
    std::size_t end = 0;
    double v = 0;
    try {
        v = std::stod(text, &end);
    } catch (const std::exception&) {
        end = 0;
    }
    const std::string unit = end ? text.substr(end) : "";
    const double scale = unit.empty() || unit == "ms" ? 1.0 : unit == "s" ? 1e3 : 0.0;
    if (!end || scale == 0 || !std::isfinite(v) || v <= 0)
        throw UsageError(fmt::format("--budget {}: a time a frame, such as 4ms or 0.004s", text));
    return v * scale;
}

// The target's error_measure in the config, or a usage error naming those it has.
const NodeDesc& targetNode(const io::RunConfig& config, const TuneTarget& t) {
    std::vector<std::string> names;
    for (const NodeDesc* n : errorMeasureNodes(config.graph)) {
        if (n->name == t.error)
            return *n;
        names.push_back(n->name);
    }
    throw UsageError(fmt::format("--target: {} has no error_measure pass '{}'{}", config.path,
                                 t.error,
                                 names.empty() ? std::string(" (it has none)")
                                               : didYouMean(t.error, names)));
}

// The parameter a sweep axis sets (a cvar, or PASS.PARAM), as the probe's chain resolves it.
std::optional<ParamInfo> sweptParam(const Bencher& bencher, const std::string& name) {
    const Plan& plan = bencher.probe().plan();
    const CvarTable& cvars = builtinCvarTable();
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
std::vector<SweepAxis> defaultSweeps(const Bencher& bencher, const TuneTarget& t) {
    SetupOptions options = bencher.options().session;
    options.dumps = {t.error + ".heat"};
    const RunSetup session(bencher.probe(), options);
    const Plan& plan = session.plan();
    std::vector<SweepAxis> sweeps;
    std::set<std::string> seenCvars;
    for (const PlanStep& step : plan.steps) {
        const PassType* type = builtinPasses().find(step.type);
        if (!type || step.io.roles.measuresError)
            continue;
        for (const ParamInfo& p : type->params) {
            if (p.cvars.empty() || seenCvars.count(p.cvars.front()))
                continue;
            SweepAxis axis{p.cvars.front(), {}};
            if (p.type == "bool")
                axis.values = {0, 1};  // as Unreal's console sets a switch
            else if (p.type == "int" && p.min && p.max && *p.max - *p.min <= 7)
                for (int v = int(*p.min); v <= int(*p.max); ++v) axis.values.push_back(v);
            else
                continue;
            for (const auto& c : p.cvars)
                seenCvars.insert(c);
            if (actsOnThisBench(bencher, axis.name))
                sweeps.push_back(std::move(axis));
        }
    }
    return sweeps;
}



// How far apart two measurements of one setting may lie: the spread of its runs, and with one
// run (no spread of its own) a tenth of its time.
double noiseMs(const TunedSetting& t) {
    const double spread = (t.setting.frame.max - t.setting.frame.min) * 1e3;
    return spread > 0 ? spread : 0.1 * t.frameMs();
}

// How many times tied settings are measured again before they are called equal.
constexpr int kTieRounds = 2;

// The work a chain does (rays, samples, texels… each pass's throughput counter, summed): what
// separates settings whose times cannot.
double chainWork(const BenchSetting& s) {
    double work = 0;
    for (const auto& p : s.passes)
        if (!p.measuresError && p.type != kBareLoopType) work += double(p.work);
    return work;
}

// The time of the target measure's method in a setting (its upstream passes), in ms.
double methodMsOf(const BenchSetting& s, const TuneTarget& t) {
    for (const auto& e : s.errors)
        if (e.name == t.error) return e.methodSeconds * 1e3;
    return 0;
}

double metricOf(const BenchSetting& s, const TuneTarget& t) {
    for (const auto& e : s.errors)
        if (e.name == t.error) {
            if (auto it = e.metrics.find(t.metric); it != e.metrics.end())
                return it->second;
        }
    throw Error(fmt::format("{} did not report {}", t.error, t.metric));
}

// A sweep value, when it is an integer.
std::optional<int> integerValue(const nlohmann::json& v) {
    return v.is_number_integer() ? std::optional<int>(v.get<int>()) : std::nullopt;
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



}  // namespace

std::string systemSettings(const SweepPoint& point) {
    std::string s = "[SystemSettings]\n";
    for (const auto& [name, value] : point)
        if (isCvarName(name))
            s += name + "=" + valueText(value) + "\n";
    return s;
}

std::string systemSettings(const TunedSetting& t) {
    // A cvar of the grid whose passes the chosen chain does not run (SSGI's quality beside a
    // ray-traced method) would read as part of the answer: say that it sets nothing instead.
    const CvarTable& cvars = builtinCvarTable();
    std::set<std::string> ran;
    for (const PassTiming& p : t.setting.passes)
        ran.insert(p.type);
    std::string s = "[SystemSettings]\n", idle;
    for (const auto& [name, value] : t.point) {
        if (!isCvarName(name))
            continue;
        const std::vector<std::string> targets = cvars.targets(name);
        const bool read = targets.empty() || std::any_of(targets.begin(), targets.end(),
                                                         [&](const auto& type) {
                                                             return ran.count(type) > 0;
                                                         });
        if (read)
            s += name + "=" + valueText(value) + "\n";
        else
            idle += fmt::format("; {}={} left out: no pass of this chain reads it\n", name,
                                valueText(value));
    }
    return s + idle;
}

std::string methodSettings(const TunedSetting& t) {
    if (std::all_of(t.point.begin(), t.point.end(),
                    [](const auto& axis) { return isCvarName(axis.first); }))
        return "";
    std::string s;
    std::set<std::string> said;
    for (const PassTiming& p : t.setting.passes)
        for (const PassType& type : builtinPasses().types()) {
            if (type.id != p.type || !said.insert(type.id).second)
                continue;
            if (!type.roles.unrealSwitch.empty())
                s += fmt::format("; the method {} runs: {}\n", type.id, type.roles.unrealSwitch);
            else if (type.roles.framepassOwn)
                s += fmt::format("; the method {} runs is framepass's own: no Unreal setting gives it\n",
                                 type.id);
        }
    return s;
}

nlohmann::json TuneResult::pointJson(const SweepPoint& point) const {
    nlohmann::json cvars = nlohmann::json::object(), params = nlohmann::json::object(),
                   inputs = nlohmann::json::object();
    for (const auto& [name, value] : point)
        (isCvarName(name) ? cvars : inputAxes.count(name) ? inputs : params)[name] = value;
    return {{"cvars", cvars}, {"params", params}, {"inputs", inputs}};
}

std::string TuneResult::bound() const {
    const std::string within = budgetMs ? fmt::format(", its method within {:g} ms", *budgetMs) : "";
    if (!std::isfinite(target.max)) return fmt::format("{} {}{}", target.error, target.metric, within);
    return fmt::format("{} {} ≤ {:g}{}", target.error, target.metric, target.max, within);
}

nlohmann::json TuneResult::toJson(const std::string& config) const {
    nlohmann::json j = {{"config", config},
                        {"target",
                         {{"error", target.error},
                          {"metric", target.metric},
                          {"max", std::isfinite(target.max) ? nlohmann::json(target.max) : nlohmann::json()}}},
                        {"met", choice.has_value()}};
    if (budgetMs) j["budgetMs"] = *budgetMs;
    auto settingJson = [this](const TunedSetting& t) {
        return nlohmann::json{{"label", t.setting.label},
                              {"setting", pointJson(t.point)},
                              {"frameMs", t.frameMs()},
                              {"methodMs", t.methodMs},
                              {"value", t.value}};
    };
    j["settings"] = nlohmann::json::array();
    for (const TunedSetting& t : tried) {
        nlohmann::json s = settingJson(t);
        s["meets"] = t.value <= target.max && (!budgetMs || t.methodMs <= *budgetMs);
        s["refined"] = t.refined;
        j["settings"].push_back(s);
    }
    if (choice) {
        j["choice"] = settingJson(tried[*choice]);
        j["systemSettings"] = systemSettings(tried[*choice]);
        j["methodSettings"] = methodSettings(tried[*choice]);
        if (!tieNote.empty()) j["tie"] = tieNote;
    } else {
        j["mostAccurate"] = settingJson(tried[mostAccurate]);
        if (inTheWay) j["inTheWay"] = inTheWay->toJson();
    }
    return j;
}

TuneResult tune(const TuneOptions& opt) {
    TuneResult result;
    result.target = parseTarget(opt.target, !opt.budget.empty());
    if (!opt.budget.empty()) result.budgetMs = parseBudgetMs(opt.budget);
    const TuneTarget& target = result.target;
    Bencher bencher(opt.bench);
    targetNode(bencher.probe().config(), target);
    std::vector<SweepAxis> sweeps;
    for (const auto& axis : opt.bench.sweeps)
        if (actsOnThisBench(bencher, axis.name))
            sweeps.push_back(axis);
    if (opt.bench.sweeps.empty()) {
        sweeps = defaultSweeps(bencher, target);
        if (sweeps.empty())
            throw UsageError(fmt::format(
                "tune: no cvar of the chain behind {} has a small domain to search; give "
                "--sweep",
                target.error));
        std::vector<std::string> texts;
        for (const auto& axis : sweeps) texts.push_back(axis.text());
        logInfo(fmt::format("tune: searching {}", fmt::join(texts, " × ")));
    }
    for (const auto& axis : sweeps)
        if (bencher.kindOf(axis.name) == SettingKind::Input) result.inputAxes.insert(axis.name);
    const std::vector<SweepPoint> grid = sweepGrid(sweeps);
    const int perSetting = opt.bench.warmup + opt.bench.runs;
    bencher.expectRuns(int(grid.size() + std::size_t(opt.refine)) * perSetting);

    std::vector<TunedSetting>& tried = result.tried;
    auto measure = [&](const SweepPoint& p, bool refined) {
        for (TunedSetting& t : tried)
            if (t.point == p)
                return;
        TunedSetting t{bencher.measure(p, false), p, 0, refined};
        t.value = metricOf(t.setting, target);
        t.methodMs = methodMsOf(t.setting, target);
        tried.push_back(std::move(t));
    };
    for (const auto& p : grid)
        measure(p, false);
    auto mostAccurateOf = [&] {
        TunedSetting* best = &tried.front();
        for (TunedSetting& t : tried)
            if (t.value < best->value) best = &t;
        return best;
    };
    if (result.budgetMs) {
        // The most accurate setting whose method fits the budget (and meets a bound if one was
        // given); the grid alone, each setting timed as bench times it.
        TunedSetting* best = nullptr;
        for (TunedSetting& t : tried)
            if (t.methodMs <= *result.budgetMs && t.value <= target.max &&
                (!best || t.value < best->value))
                best = &t;
        if (best) result.choice = std::size_t(best - tried.data());
        result.mostAccurate = std::size_t(mostAccurateOf() - tried.data());
        return result;
    }

    // Refine: bisect the one integer axis between the cheapest setting that meets the target
    // and the next faster setting of the Pareto front, while values lie between them.
    auto cheapestMeeting = [&]() -> TunedSetting* {
        TunedSetting* best = nullptr;
        for (TunedSetting& t : tried)
            if (t.value <= target.max && (!best || t.frameMs() < best->frameMs()))
                best = &t;
        return best;
    };
    for (int round = 0; round < opt.refine; ++round) {
        TunedSetting* meets = cheapestMeeting();
        if (!meets)
            break;
        // The fastest setting that is cheaper and more accurate than every other cheaper one:
        // the front's point just below the choice.
        TunedSetting* below = nullptr;
        for (TunedSetting& t : tried) {
            if (t.frameMs() >= meets->frameMs())
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
        p[*axis].second = mid;
        const std::size_t before = tried.size();
        measure(p, true);
        if (tried.size() == before)
            break;
    }

    // Times closer than their noise do not order two settings: measure both again, and
    // if they stay that close, call them equal and take the one that does less work.
    TunedSetting* choice = cheapestMeeting();
    std::string& tieNote = result.tieNote;
    for (int round = 0; choice && round <= kTieRounds; ++round) {
        std::vector<TunedSetting*> ties;
        for (TunedSetting& t : tried)
            if (&t != choice && t.value <= target.max &&
                std::fabs(t.frameMs() - choice->frameMs()) <= noiseMs(t) + noiseMs(*choice))
                ties.push_back(&t);
        if (ties.empty()) break;
        if (round == kTieRounds) {
            TunedSetting* least = choice;
            for (TunedSetting* t : ties)
                if (chainWork(t->setting) < chainWork(least->setting)) least = t;
            tieNote = fmt::format(
                "{} setting(s) within the timing noise of {} after {} more measurement(s): "
                "taken as equal, the one with the least work chosen",
                ties.size(), choice->setting.label, kTieRounds);
            choice = least;
            break;
        }
        ties.push_back(choice);
        for (TunedSetting* t : ties) {
            t->setting = bencher.measure(t->point, false);
            t->value = metricOf(t->setting, target);
        }
        choice = cheapestMeeting();
    }
    TunedSetting* mostAccurate = mostAccurateOf();
    if (!choice && opt.bench.decomposeRays > 0) {
        BenchSetting again = bencher.measure(mostAccurate->point, true);
        for (const auto& e : again.errors)
            if (e.name == target.error && e.decomposition)
                result.inTheWay = e.decomposition;
    }

    if (choice)
        result.choice = std::size_t(choice - tried.data());
    result.mostAccurate = std::size_t(mostAccurate - tried.data());
    return result;
}

}  // namespace fp::app
