// framepass tune: the cheapest setting whose error meets a target (app/Tune.h does the search).
#include "app/Tune.h"
#include "cli/Commands.h"
#include "cli/Flags.h"

#include <algorithm>
#include <iostream>

namespace fp::cli {

Command addTuneCommand(CLI::App& app) {
    auto opt = std::make_shared<app::TuneOptions>();
    CLI::App* sub = app.add_subcommand(
        "tune",
        "find the cheapest setting whose error meets a target: a grid, then refined along the "
        "Pareto front; prints it as an Unreal [SystemSettings] snippet");
    addSetupOptions(*sub, opt->bench.session);
    sub->add_option("--target", opt->target,
                    "ERROR_PASS<=VALUE (its RMSE) or ERROR_PASS.METRIC<=VALUE (rmse, relMse, "
                    "smape, mae, maxError, overTolerance)")
        ->required();
    addSweepOption(*sub, opt->bench.sweeps,
                   "the grid, as bench's --sweep (default: every cvar of the measured chain "
                   "that is a switch or an integer of at most 8 values)");
    sub->add_option("--budget", opt->budget,
                    "instead, the most accurate setting whose method (the passes the target's "
                    "source depends on) takes at most this a frame: 4ms, 0.004s (--target may "
                    "then name the measure alone)");
    sub->add_option("--refine", opt->refine,
                    "settings at most to try between grid values along the Pareto front "
                    "(default 4)")
        ->check(CLI::Range(0, 100));
    opt->bench.runs = 3;  // tune's default: a grid of settings, each timed
    addTimingOptions(*sub, opt->bench);
    addDecomposeRaysOption(*sub, opt->bench.decomposeRays,
                           "rays of the error decomposition shown when nothing meets the target "
                           "(default 256; 0: none)");
    sub->add_flag("--json", opt->bench.json, "print the result as JSON");

    return [opt]() {
        const app::TuneResult r = app::tune(*opt);
        if (opt->bench.json) {
            std::cout << r.toJson(opt->bench.session.config).dump(2) << "\n";
            return r.choice ? 0 : 1;
        }
        std::size_t refined = 0;
        for (const auto& t : r.tried)
            refined += t.refined ? 1 : 0;
        std::cout << fmt::format("tune {}: {} over {} settings ({} on the grid, {} refined)\n",
                                 opt->bench.session.config, r.bound(), r.tried.size(),
                                 r.tried.size() - refined, refined);
        for (const auto& t : r.tried) {
            const bool fits = !r.budgetMs || t.methodMs <= *r.budgetMs;
            std::cout << fmt::format("  {:<48} {:>9.2f} ms  {} {:.5g}{}{}{}\n", t.setting.label,
                                     t.frameMs(), r.target.metric, t.value,
                                     r.budgetMs ? fmt::format("  method {:.2f} ms", t.methodMs) : "",
                                     t.value <= r.target.max && fits ? (r.budgetMs ? "  fits" : "  meets") : "",
                                     t.refined ? "  (refined)" : "");
        }
        if (!r.tieNote.empty()) std::cout << r.tieNote << "\n";
        if (r.choice) {
            const auto& c = r.tried[*r.choice];
            if (r.budgetMs)
                std::cout << fmt::format("most accurate setting, {}: {} (its method {:.2f} ms, {} "
                                         "{:.5g})\n",
                                         r.bound(), c.setting.label, c.methodMs, r.target.metric,
                                         c.value);
            else
                std::cout << fmt::format("cheapest setting that meets {}: {} ({:.2f} ms, {} {:.5g})\n",
                                         r.bound(), c.setting.label, c.frameMs(), r.target.metric,
                                         c.value);
            std::cout << app::systemSettings(c);
            for (const auto& [name, value] : c.point)
                if (!app::isCvarName(name))
                    std::cout << fmt::format("; framepass only (no Unreal cvar): --{} {}={}\n",
                                             r.inputAxes.count(name) ? "input" : "set", name,
                                             app::valueText(value));
            std::cout << app::methodSettings(c);
            return 0;
        }
        const auto& m = r.tried[r.mostAccurate];
        if (r.budgetMs) {
            const auto fastest = std::min_element(r.tried.begin(), r.tried.end(), [](const auto& a, const auto& b) {
                return a.methodMs < b.methodMs;
            });
            std::cout << fmt::format("no setting meets {}: the fastest method, {}, takes {:.2f} ms\n",
                                     r.bound(), fastest->setting.label, fastest->methodMs);
            return 1;
        }
        std::cout << fmt::format("no setting meets {}: the most accurate, {}, has {} {:.5g} "
                                 "({:.2f} ms)\n",
                                 r.bound(), m.setting.label, r.target.metric, m.value, m.frameMs());
        if (r.inTheWay)
            std::cout << "what stands in the way:\n" << app::decompositionText(*r.inTheWay);
        return 1;
    };
}

}  // namespace fp::cli
