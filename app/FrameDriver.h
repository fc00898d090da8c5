#pragma once
// The one place frames run. Everything that runs a plan on a capture's frames — `run`, a
// Session, bench and tune, the error breakdown — asks a FrameDriver, which owns what carries from
// one frame to the next:
//  - the temporal passes' history, by one rule: a frame that follows the last frame run (the next
//    of the sequence, or the next number) continues its history; the same frame again starts
//    from the history it had before; any other frame, or any frame after cut(), starts a
//    sequence;
//  - the captures read, kept as its user needs them (CaptureKeeping), and the next frame's
//    capture read ahead while one runs;
//  - with `incremental`, a StepCache: the steps unchanged since the last run are not executed;
//  - how long each frame's input took to read and decode.
// The sinks that take a frame's outputs are its users' (files through io::OutputQueue, images
// kept in memory); the driver hands them to the executor.
#include "app/BenchSources.h"
#include "app/RunSetup.h"
#include "framework/Executor.h"
#include "io/CaptureReadAhead.h"

#include <map>
#include <memory>
#include <optional>
#include <vector>

namespace fp::app {

/// Which captures a driver keeps decoded after their frame ran.
enum class CaptureKeeping {
    /// None: each frame's capture is read for it (ahead of it with `readAhead`) and dropped once
    /// the next frame runs. `run` over a sequence.
    Streaming,
    /// The frame run last and the one before it, each buffer read once: a look-dev session that
    /// runs a frame again after a change.
    Neighbours,
    /// Every frame's buffers, read once: bench's repeated runs time the passes, not the disk.
    Every,
};

struct FrameDriverOptions {
    CaptureKeeping keep = CaptureKeeping::Streaming;
    /// How many of the next frames (run()'s `next`) are read while a frame runs, each on a thread
    /// of its own; each holds a frame's capture buffers. 0: a frame reads its capture as it runs.
    int readAhead = 0;
    /// Keep every step's outputs (StepCache): a step unchanged since the last run is not run.
    bool incremental = false;
    /// Bad input pixels and assumed values are errors (run's --strict).
    bool strict = false;
};

/// One frame as the driver ran it.
struct FrameRun {
    FrameReport report;
    /// Reading this frame's files and decoding them, wherever it happened (ahead, on the
    /// read-ahead thread, or in the frame).
    FrameSource::InputSeconds input;
    /// The capture's files the frame read (their notes, read log, sanitised values); null for a
    /// capture held in memory. Valid until the next run().
    io::CaptureSource* capture = nullptr;
};

class FrameDriver {
public:
    /// Runs frames of `capture`'s capture (its files, profile, scene; it must outlive the
    /// driver). The plans it runs may be any made from the same config and capture: a session's
    /// after each change, bench's sweep points.
    FrameDriver(const RunSetup& capture, FrameDriverOptions options);
    ~FrameDriver();

    /// The frames in the order they run, when more than the setup's (warm-up frames first): a
    /// frame continues the history of the one before it here.
    void setSequence(std::vector<int> frames) { mSequence = std::move(frames); }

    /// Runs `plan` on `frame` into `sink`; `progress` is called after each pass (it may throw to stop the
    /// frame between passes). `next`: the frames that run after it, in order; the first
    /// `readAhead` of them are read while this one runs. A frame that
    /// throws leaves the history as it was before it. Throws fp::Error for the frame.
    FrameRun run(const Plan& plan, int frame, FrameSink& sink, const ProgressFn& progress = {},
                 const std::vector<int>& next = {});
    /// Runs `plan` once on `frame`'s capture (read once and kept with the frame), apart from the
    /// sequence: no history, no StepCache, its random numbers seeded as frame `seed`. The error
    /// breakdown's oracle and converged chains.
    FrameReport runApart(const Plan& plan, int frame, FrameSink& sink, int64_t seed,
                         const ProgressFn& progress = {});
    /// The next frame starts a sequence (a failed or skipped frame, a new timed run).
    void cut();
    /// Forgets the StepCache's outputs: the next run executes every pass.
    void forgetOutputs() { mCache.clear(); }

    /// `frame`'s capture, each buffer read once and kept while the driver keeps the frame.
    CachedSource& source(int frame);

private:
    struct Kept {
        std::unique_ptr<FrameSource> capture;  // the frame's files, or the capture in memory
        std::unique_ptr<CachedSource> cached;  // made when the frame is kept or asked for
    };
    Kept& open(int frame, std::unique_ptr<io::CaptureSource> readAhead = nullptr);
    bool follows(int last, int frame) const;
    io::CaptureSource::Options captureOptions(int frame) const;

    const RunSetup& mSetup;
    FrameDriverOptions mOptions;
    std::vector<int> mSequence;
    std::map<int, Kept> mKept;
    io::CaptureReadAhead mReadAhead;
    StepCache mCache;
    HistoryStore mHistory, mHistoryBefore;  // now, and before the last frame run
    std::optional<int> mLast;
    bool mLastFirst = true, mCut = false;
};

}  // namespace fp::app
