#pragma once
// A sequence's next frame read while the current one runs: its capture opened and the buffers
// its plan reads decoded on a worker thread, so frame N+1's file reading overlaps frame N's
// passes (on the GPU, the frame then starts with its capture in memory and only the copies to
// the GPU left). Reading ahead changes no output: the frame reads the same buffers through the
// same code, only earlier. Whatever goes wrong while reading ahead is left for the frame itself
// to meet again in its own place, so errors name the frame they belong to.
#include "io/CaptureSource.h"

#include <atomic>
#include <future>
#include <memory>
#include <vector>

namespace fp::io {

class CaptureReadAhead {
public:
    CaptureReadAhead() = default;
    CaptureReadAhead(const CaptureReadAhead&) = delete;
    CaptureReadAhead& operator=(const CaptureReadAhead&) = delete;
    /// Waits for a read still under way (asking it to stop first).
    ~CaptureReadAhead();

    /// Starts reading frame `options.frame`: its capture opened with `profile`, its header and
    /// camera read, then `reads` in order. A read already under way is stopped and dropped.
    void start(CaptureOptions options, const CaptureProfile& profile,
               std::vector<CaptureRead> reads);
    /// Frame `frame`'s source with its buffers read, waiting for the read to end; null when no
    /// read of that frame was started or it could not open the capture (the caller opens it
    /// again, meeting the error in the frame's place).
    std::unique_ptr<CaptureSource> take(int64_t frame);

private:
    void stop();
    int64_t mFrame = 0;
    std::atomic<bool> mCancelled{false};
    std::future<std::unique_ptr<CaptureSource>> mRead;
};

}  // namespace fp::io
