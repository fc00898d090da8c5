// framepass bench: runs a chain several times on one frame and reports each pass's median time
// and throughput; --sweep varies cvars or parameters over a grid and, where the chain measures
// error against truth (error_measure passes), produces the speed-against-error table, its Pareto
// front, the error taken apart, and an HTML report.
#include "app/BenchResult.h"
#include "app/BenchSweep.h"
#include "cli/Commands.h"
#include "cli/Flags.h"
#include "app/Invocation.h"
#include "io/SafeFiles.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace fp::cli {

namespace {

void printBench(const BenchResult& result) {
    // A sequence: every run goes through its frames with history; times are per frame.
    const std::string frames =
        result.frames.size() > 1
            ? fmt::format("frames {}, each run in order with history; times per frame, errors "
                          "on frame {}",
                          fmt::join(result.frames, ","), result.frame)
            : fmt::format("frame {}", result.frame);
    std::cout << fmt::format("{} on {} ({}, {}×{}): median of {} runs after {} warm-up, "
                             "{} threads\n",
                             result.config, result.capture, frames, result.extent.width,
                             result.extent.height, result.runs, result.warmup, result.threads);
    for (const auto& s : result.settings) {
        std::cout << fmt::format("{}: frame {:.2f} ms (min {:.2f}, max {:.2f}), peak {:.1f} MiB "
                                 "({:.0f} B/pixel)",
                                 s.label, s.frame.median * 1e3, s.frame.min * 1e3,
                                 s.frame.max * 1e3, double(s.peakBytes) / 1048576.0,
                                 double(s.peakBytes) / (double(result.extent.width) * result.extent.height));
        if (s.hasError())
            std::cout << fmt::format(", RMSE {:.5g}{}", s.error(), s.pareto ? " [Pareto]" : "");
        std::cout << "\n";
        // The name column fits the longest name (the bare loops' are long), at least 24 wide.
        std::size_t nameWidth = 24;
        for (const auto& p : s.passes)
            nameWidth = std::max(nameWidth, p.name.size());
        for (const auto& p : s.passes) {
            std::cout << fmt::format("  {:<{}} {:>9.2f} ms  (min {:.2f}, max {:.2f})", p.name,
                                     nameWidth, p.seconds.median * 1e3, p.seconds.min * 1e3,
                                     p.seconds.max * 1e3);
            if (p.work)
                std::cout << fmt::format("  {:.2f} M{}/s", p.throughput() * 1e-6, p.unit);
            if (p.gpuSeconds)
                std::cout << fmt::format("  [gpu {:.3f} ms by CUDA events]",
                                         p.gpuSeconds->median * 1e3);
            if (p.bareSeconds)
                std::cout << fmt::format("  {:.0f} % of Embree's speed (its bare loops one ray "
                                         "at a time: {:.2f} ms)",
                                         p.bareRatio() * 100, *p.bareSeconds * 1e3);
            std::cout << "\n";
        }
        for (const auto& e : s.errors) {
            std::string m;
            for (const auto& [k, v] : e.metrics)
                m += fmt::format(" {}={:.5g}", k, v);
            std::cout << fmt::format("  {} ({} against {}):{}\n", e.name, e.source, e.reference, m);
            if (!e.methodPasses.empty())
                std::cout << fmt::format("    the method: {:.2f} ms ({})\n", e.methodSeconds * 1e3,
                                         fmt::join(e.methodPasses, ", "));
            if (!e.rmseByFrame.empty())
                std::cout << fmt::format("    RMSE by frame: {:.5g}\n", fmt::join(e.rmseByFrame, " → "));
            if (e.decomposition)
                std::cout << decompositionText(*e.decomposition);
        }
    }
}

void printIncremental(const IncrementalTiming& t) {
    std::cout << fmt::format("incremental re-run after {} changes ({}): {:.2f} ms (min {:.2f}, "
                             "max {:.2f}) against {:.2f} ms for the whole frame; {} of {} "
                             "passes executed: {}\n",
                             t.setting, fmt::join(t.values, " ↔ "), t.rerun.median * 1e3,
                             t.rerun.min * 1e3, t.rerun.max * 1e3, t.frame.median * 1e3,
                             t.executed.size(), t.passes, fmt::join(t.executed, ", "));
}

void writeHtml(const BenchResult& result, const std::string& path) {
    io::writeFileAtomically(path, benchHtml(result));
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
    auto opt = std::make_shared<BenchOptions>();
    auto incremental = std::make_shared<std::string>();
    CLI::App* sub = app.add_subcommand(
        "bench",
        "time the chain over several runs (median, min, max, throughput per pass); "
        "--sweep gives the speed-against-error table");
    addSetupOptions(*sub, opt->session);
    addTimingOptions(*sub, *opt);
    addSweepOption(*sub, opt->sweeps,
                   "vary a cvar or PASS.PARAM: NAME=V1,V2,... or NAME=A..B; several make a grid");
    sub->add_flag("--json", opt->json, "print the results as JSON");
    sub->add_option("--html", opt->html, "write a self-contained HTML report here")
        ->check(nonEmptyPath());
    addDecomposeRaysOption(*sub, opt->decomposeRays,
                           "rays per pixel of the error decomposition's oracle and converged "
                           "tracer (default 256); 0 leaves the decomposition out");
    sub->add_option("--incremental", *incremental,
                    "NAME=A,B: also time a look-dev session's re-run after NAME (a cvar or "
                    "PASS.PARAM) changes between A and B, which executes only the passes "
                    "downstream of it, beside a whole frame");

    return [opt, incremental]() {
        if (!opt->html.empty()) io::checkWritable(opt->html, "--html");
        const BenchResult result = runBench(*opt, *incremental);

        if (opt->json)
            std::cout << result.toJson().dump(2) << "\n";
        else
            printBench(result);
        if (!opt->json && result.incremental)
            printIncremental(*result.incremental);
        if (!opt->html.empty()) {
            writeHtml(result, opt->html);
            if (!opt->json)
                std::cout << "wrote " << opt->html << "\n";
        }
        return 0;
    };
}

}  // namespace fp::cli