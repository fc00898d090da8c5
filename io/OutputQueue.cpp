#include "io/OutputQueue.h"

#include <algorithm>

namespace fp::io {

OutputQueue::OutputQueue(OutputWriter& writer, int writers) : mWriter(writer) {
    for (int i = 0; i < writers; ++i) mThreads.emplace_back([this] { work(); });
}

OutputQueue::~OutputQueue() {
    {
        const std::lock_guard<std::mutex> lock(mMutex);
        mStopping = true;
    }
    mWake.notify_all();
    for (auto& t : mThreads) t.join();
}

void OutputQueue::write(const OutputDesc& output, const std::vector<OutputLayer>& layers,
                        const FrameInfo& frame) {
    Job job{frame.number, 0, output, {}, {}, {}, frame};
    for (const auto& l : layers) {
        job.names.push_back(l.name);
        job.textures.push_back(*l.texture);
        job.kinds.push_back(l.kind);
    }
    std::unique_lock<std::mutex> lock(mMutex);
    Frame& f = mFrames[frame.number];
    job.index = f.queued++;
    f.files.resize(f.queued);
    f.errors.resize(f.queued);
    if (mThreads.empty()) {
        lock.unlock();
        run(job);  // errors go to the caller, as OutputWriter's do
        return;
    }
    mJobs.push_back(std::move(job));
    lock.unlock();
    mWake.notify_one();
}

void OutputQueue::run(Job& job) {
    std::vector<OutputLayer> layers;
    for (std::size_t i = 0; i < job.textures.size(); ++i)
        layers.push_back({job.names[i], &job.textures[i], job.kinds[i]});
    OutputWriter::WrittenFile file;
    std::exception_ptr error;
    try {
        file = mWriter.writeFile(job.output, layers, job.info);
    } catch (...) {
        error = std::current_exception();
    }
    job.textures.clear();  // the pixels go back before the frame is said to be done
    {
        const std::lock_guard<std::mutex> lock(mMutex);
        Frame& f = mFrames[job.frame];
        f.files[job.index] = std::move(file);
        f.errors[job.index] = error;
        ++f.done;
    }
    mDone.notify_all();
    if (error && mThreads.empty()) std::rethrow_exception(error);
}

void OutputQueue::work() {
    for (;;) {
        std::unique_lock<std::mutex> lock(mMutex);
        mWake.wait(lock, [&] { return mStopping || !mJobs.empty(); });
        if (mJobs.empty()) return;  // stopping, and nothing left to write
        Job job = std::move(mJobs.front());
        mJobs.pop_front();
        lock.unlock();
        run(job);
    }
}

OutputQueue::FrameFiles OutputQueue::finish(int64_t frame) {
    std::unique_lock<std::mutex> lock(mMutex);
    auto it = mFrames.find(frame);
    if (it == mFrames.end()) return {};
    mDone.wait(lock, [&] { return it->second.done == it->second.queued; });
    FrameFiles out;
    for (const auto& e : it->second.errors)
        if (e && !out.error) out.error = e;
    for (const auto& f : it->second.files) {
        if (f.path.empty()) continue;  // failed
        out.written.push_back(f.path);
        out.encodeSeconds += f.encodeSeconds;
        out.writeSeconds += f.writeSeconds;
    }
    mFrames.erase(it);
    return out;
}

}  // namespace fp::io
