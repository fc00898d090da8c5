#pragma once
// The writing end of a sequence's pipeline: a frame's outputs are handed to a pool of writer
// threads as the executor finishes them, so frame N's files are encoded and written while frame
// N+1 computes. Each file still goes through OutputWriter (checked, encoded in memory, written to
// a temporary and renamed), so a final name never holds part of a file. The queue keeps the
// images of the files it has not written yet (their pixels shared, not copied) and nothing more;
// its user bounds how many frames are in flight (app/FrameDriver: the frame computing and the
// one before it).
#include "io/OutputWriter.h"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace fp::io {

class OutputQueue final : public FrameSink {
public:
    /// `writers` threads write through `writer`; 0 writes each file on the caller's thread, in
    /// write(), as OutputWriter alone does.
    OutputQueue(OutputWriter& writer, int writers);
    /// Waits for every file queued (their errors are dropped: finish() is where they are said).
    ~OutputQueue();
    OutputQueue(const OutputQueue&) = delete;
    OutputQueue& operator=(const OutputQueue&) = delete;

    void write(const OutputDesc& output, const std::vector<OutputLayer>& layers,
               const FrameInfo& frame) override;

    /// What a frame's files took, once all of them are written.
    struct FrameFiles {
        std::vector<std::string> written;  //!< in the order the frame handed them over
        double encodeSeconds = 0, writeSeconds = 0;  //!< summed over its files
        /// The error of the first file, in the frame's order, that failed (an fp::Error), or null:
        /// the error a run writing on the frame's thread would have met first.
        std::exception_ptr error;
    };
    /// Waits until every file `frame` handed over is written (or failed) and forgets the frame.
    FrameFiles finish(int64_t frame);
    int writers() const { return int(mThreads.size()); }

private:
    struct Job {
        int64_t frame = 0;
        std::size_t index = 0;  // its place among the frame's files
        OutputDesc output;
        std::vector<std::string> names;
        std::vector<Texture> textures;  // shallow copies: the pixels stay alive until written
        std::vector<PortKind> kinds;
        FrameInfo info;
    };
    struct Frame {
        std::size_t queued = 0, done = 0;
        std::vector<OutputWriter::WrittenFile> files;  // by index
        std::vector<std::exception_ptr> errors;        // by index
    };
    void work();
    void run(Job& job);

    OutputWriter& mWriter;
    mutable std::mutex mMutex;
    std::condition_variable mWake, mDone;
    std::deque<Job> mJobs;
    std::map<int64_t, Frame> mFrames;
    bool mStopping = false;
    std::vector<std::thread> mThreads;
};

}  // namespace fp::io
