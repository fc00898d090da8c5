#pragma once
// framepass run's work: the chain over every frame of the config (warm-up frames first when
// asked) through the frame driver, the next frames' captures read ahead, each frame's outputs
// and dumps written by io::OutputQueue's writers while the next frame computes, a report of every
// frame (its stages' seconds), pass and input file, each screen-space error taken apart when
// asked. The CLI's `run` is this and its flags; anything else that writes a sequence to disk calls
// it too.
#include "app/RunSetup.h"

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace fp::app {

struct RunOptions {
    SetupOptions setup;
    std::string outputDir = "out";
    std::string report;  //!< JSON report path; "-" = `out` (the frame lines then go to `err`)
    bool continueOnError = false;  //!< attempt every frame, list the failed ones
    bool skipExisting = false;     //!< skip frames whose outputs all exist
    int warmupFrames = 0;          //!< frames before the first, run for history only
    int decomposeRays = 0;         //!< 0: no error breakdown
    std::string maxMemory;         //!< "8G", ""= the default limit (MemoryLimit.h)
    std::string tev;               //!< HOST:PORT of a tev viewer to push outputs to; "" = none
    /// Frames whose captures are read, each on a thread of its own, while a frame runs
    /// (--read-ahead; each holds a frame's capture buffers); 0 reads each at its frame's start;
    /// -1: defaultReadAhead().
    int readAhead = -1;
    /// Threads that encode and write a frame's files while the next frame computes (--writers);
    /// 0 writes each file on the frame's thread as soon as it is made; -1: defaultWriters().
    int writers = -1;
};

/// The defaults for `threads` cores (the --threads in force): a quarter of them each reading
/// ahead (1 to 4 frames) and writing (2 to 8 writers). A GPU's frame leaves the cores to the
/// files: on 16 cores, one reader and two writers left the H200's passes idle 97 % of the time.
int defaultReadAhead(int threads);
int defaultWriters(int threads);

struct RunOutcome {
    nlohmann::json report;          //!< what --report writes
    std::vector<int> failedFrames;  //!< with continueOnError
    int frames = 0;
};

/// Runs every frame. Frame lines go to `out` (to `err` when the report goes to `out`); a failed
/// frame with continueOnError is said on `err`. Throws fp::Error for the first failed frame
/// otherwise, and fp::Interrupted when a stop is requested (the report is written first).
RunOutcome runFrames(const RunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace fp::app
