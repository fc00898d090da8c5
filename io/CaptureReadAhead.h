#pragma once
// A sequence's next frames read while the current one runs: each frame's capture opened and the
// buffers its plan reads decoded on a thread of its own, so frames N+1, N+2… are read and decoded
// while frame N's passes run (on the GPU, a frame then starts with its capture in memory and only
// the copies to the GPU left; on many cores, several frames decode at once). Reading ahead changes
// no output: a frame reads the same buffers through the same code, only earlier. Whatever goes
// wrong while reading ahead is left for the frame itself to meet again in its own place, so errors
// name the frame they belong to.
#include "io/CaptureSource.h"

#include <atomic>
#include <deque>
#include <future>
#include <memory>
#include <vector>

namespace fp::io {

class CaptureReadAhead {
public:
    CaptureReadAhead() = default;
    CaptureReadAhead(const CaptureReadAhead&) = delete;
    CaptureReadAhead& operator=(const CaptureReadAhead&) = delete;
    /// Waits for the reads still under way (asking them to stop first).
    ~CaptureReadAhead();

    /// Starts reading frame `options.frame` on a thread of its own: its capture opened with
    /// `profile`, its header and camera read, then `reads` in order. Nothing happens when that
    /// frame is being read already; reads of other frames go on.
    void start(CaptureOptions options, const CaptureProfile& profile,
               std::vector<CaptureRead> reads);
    /// How many frames are being read (or wait, read, to be taken).
    std::size_t inFlight() const { return mPending.size(); }
    /// Frame `frame`'s source with its buffers read, waiting for the read to end. The reads
    /// started before it are stopped and dropped (the sequence has moved past them); those
    /// started after it go on. Null when no read of that frame was started (every read is then
    /// dropped) or it could not open the capture (the caller opens it again, meeting the error in
    /// the frame's place).
    std::unique_ptr<CaptureSource> take(int64_t frame);

private:
    struct Pending {
        int64_t frame = 0;
        std::shared_ptr<std::atomic<bool>> cancelled;
        std::future<std::unique_ptr<CaptureSource>> read;
    };
    static void stop(Pending& p);
    std::deque<Pending> mPending;  // in the order started
};

}  // namespace fp::io
