// framepass run: execute the chain over the frames and write outputs, dumps and a report
// (app/RunFrames.h does the work).
#include "app/RunFrames.h"
#include "cli/Commands.h"
#include "cli/Flags.h"
#include "foundation/Error.h"

#include <fmt/ranges.h>

#include <iostream>

namespace fp::cli {

Command addRunCommand(CLI::App& app) {
    auto opt = std::make_shared<app::RunOptions>();
    CLI::App* sub = app.add_subcommand("run", "run the chain and write the requested outputs");
    addSetupOptions(*sub, opt->setup);
    sub->add_option("-o,--output-dir", opt->outputDir, "folder for outputs (default: out)")
        ->check(nonEmptyPath());
    sub->add_option("--report", opt->report,
                    "write a JSON report (atomically, even when a frame fails or the run is "
                    "stopped): per-frame status, per-pass time and work counts, every input "
                    "file; - = stdout (the frame lines then go to stderr)")
        ->check(nonEmptyPath());
    sub->add_flag("--strict", opt->setup.strict,
                  "fail on NaN/Inf/negative input pixels, on assumed camera values and on a "
                  "--cvars file that gives no cvar, instead of sanitizing, assuming or warning");
    sub->add_option("--warmup-frames", opt->warmupFrames,
                    "run N frames before the first one (writing nothing) so temporal passes "
                    "start with history: a chunked farm run then equals a sequential one")
        ->check(CLI::Range(0, 100000));
    addDecomposeRaysOption(*sub, opt->decomposeRays,
                           "take each screen-space error apart (as bench does) with N rays per "
                           "pixel, every frame, into the output and the report (default 0: off)");
    sub->add_flag("--continue-on-error", opt->continueOnError,
                  "attempt every frame; exit 1 at the end listing the frames that failed");
    addMaxMemoryOption(*sub, opt->maxMemory);
    sub->add_option("--read-ahead", opt->readAhead,
                    "frames whose captures are read, each on a thread of its own, while a frame "
                    "runs (default: a quarter of the threads, 1 to 4); each holds a frame's "
                    "capture buffers")
        ->check(CLI::Range(0, 64));
    sub->add_flag_callback("--no-read-ahead", [opt] { opt->readAhead = 0; },
                           "--read-ahead 0: read each frame's capture at its start");
    sub->add_option("--writers", opt->writers,
                    "threads that encode and write a frame's files while the next frame "
                    "computes (default: a quarter of the threads, 2 to 8); 0 writes each file "
                    "as soon as it is made, on the frame's thread")
        ->check(CLI::Range(0, 64));
    sub->add_flag("--skip-existing", opt->skipExisting,
                  "skip frames whose outputs all exist (a re-queued farm task); with temporal "
                  "passes the skipped frames before a computed one still run, writing nothing");

    sub->add_option("--tev", opt->tev,
                    "also push every output layer to a running tev viewer as an image of that "
                    "name (HOST:PORT; default 127.0.0.1:14158)")
        ->expected(0, 1)
        ->default_str("127.0.0.1:14158");

    return [opt]() {
        catchStopSignals();
        const app::RunOutcome outcome = app::runFrames(*opt, std::cout, std::cerr);
        if (outcome.failedFrames.empty())
            return 0;
        std::cerr << fmt::format("framepass: {} of {} frame(s) failed: {}\n",
                                 outcome.failedFrames.size(), outcome.frames,
                                 fmt::join(outcome.failedFrames, ","));
        return int(ExitCode::FrameFailed);
    };
}

}  // namespace fp::cli
