#include "app/FrameDriver.h"

#include "foundation/Error.h"
#include "io/MemoryCapture.h"

#include <algorithm>

namespace fp::app {

namespace {
// A frame as one run sees it: whether it starts a sequence, and the frame number that seeds its
// passes' random numbers (the error breakdown averages one capture over several); the rest is
// the capture's.
class FrameView final : public ForwardingSource {
public:
    FrameView(FrameSource& inner, bool firstInSequence, std::optional<int64_t> seed = {})
        : ForwardingSource(inner), mFirst(firstInSequence), mSeed(seed) {}
    FrameInfo frameInfo() override {
        FrameInfo info = mInner.frameInfo();
        info.firstInSequence = mFirst;
        if (mSeed) info.number = *mSeed;
        return info;
    }

private:
    bool mFirst;
    std::optional<int64_t> mSeed;
};

FrameSource::InputSeconds minus(FrameSource::InputSeconds a, FrameSource::InputSeconds b) {
    return {a.read - b.read, a.decode - b.decode};
}
}  // namespace

FrameDriver::FrameDriver(const RunSetup& setup, FrameDriverOptions options)
    : mSetup(setup), mOptions(options) {}

FrameDriver::~FrameDriver() = default;

io::CaptureSource::Options FrameDriver::captureOptions(int frame) const {
    io::CaptureSource::Options o = mSetup.captureOptions(frame);
    o.strict = mOptions.strict;
    return o;
}

FrameDriver::Kept& FrameDriver::open(int frame, std::unique_ptr<io::CaptureSource> readAhead) {
    // What is kept besides this frame: nothing (Streaming), the frame before (Neighbours), all.
    if (mOptions.keep != CaptureKeeping::Every)
        std::erase_if(mKept, [&](const auto& entry) {
            return entry.first != frame &&
                   !(mOptions.keep == CaptureKeeping::Neighbours && entry.first == frame - 1);
        });
    Kept& kept = mKept[frame];
    if (readAhead) {
        kept = {std::move(readAhead), nullptr};
    } else if (!kept.capture) {
        if (mSetup.memoryCapture())
            kept.capture =
                std::make_unique<io::MemoryCaptureSource>(mSetup.memoryCapture(), captureOptions(frame));
        else
            kept.capture = std::make_unique<io::CaptureSource>(captureOptions(frame),
                                                               mSetup.profile());
    }
    if (!kept.cached && mOptions.keep != CaptureKeeping::Streaming)
        kept.cached = std::make_unique<CachedSource>(*kept.capture);
    return kept;
}

CachedSource& FrameDriver::source(int frame) {
    auto it = mKept.find(frame);
    Kept& kept = it != mKept.end() ? it->second : open(frame);
    if (!kept.cached) kept.cached = std::make_unique<CachedSource>(*kept.capture);
    return *kept.cached;
}

bool FrameDriver::follows(int last, int frame) const {
    const std::vector<int>& order = mSequence.empty() ? mSetup.frames() : mSequence;
    const auto at = std::find(order.begin(), order.end(), last);
    if (at != order.end() && at + 1 != order.end()) return *(at + 1) == frame;
    return frame == last + 1;
}

void FrameDriver::cut() {
    mCut = true;
    mHistory.clear();
    mHistoryBefore.clear();
}

FrameRun FrameDriver::run(const Plan& plan, int frame, FrameSink& sink,
                          const ProgressFn& progress, const std::vector<int>& next) {
    // The history this frame starts from (the rule in FrameDriver.h).
    bool first = true;
    if (!mCut && mLast && frame == *mLast) {
        mHistory = mHistoryBefore;
        first = mLastFirst;
    } else if (!mCut && mLast && follows(*mLast, frame)) {
        mHistoryBefore = mHistory;
        first = false;
    } else {
        mHistory.clear();
        mHistoryBefore.clear();
    }
    mCut = false;
    mLast = frame;
    mLastFirst = first;

    // The capture: read ahead, kept from an earlier run, or opened now.
    std::unique_ptr<io::CaptureSource> readAhead =
        mOptions.readAhead > 0 ? mReadAhead.take(frame) : nullptr;
    const bool fresh = readAhead || !mKept.count(frame);
    Kept& kept = open(frame, std::move(readAhead));
    FrameSource& capture = kept.cached ? static_cast<FrameSource&>(*kept.cached) : *kept.capture;
    const FrameSource::InputSeconds before =
        fresh ? FrameSource::InputSeconds{} : capture.inputSeconds();
    FrameView view(capture, first);
    FP_CHECK(!plan.needsCamera || view.frameInfo().hasCamera,
             "{}: frame {}: no camera in the header and no sidecar ({}.camera.json)",
             mSetup.capturePath(frame), frame, mSetup.capturePath(frame));
    if (!mSetup.memoryCapture())
        for (std::size_t i = 0; i < next.size() && int(i) < mOptions.readAhead; ++i)
            mReadAhead.start(captureOptions(next[i]), mSetup.profile(), plan.captureReads);

    FrameRun result;
    if (mOptions.incremental) mCache.sourceId = mSetup.capturePath(frame);
    try {
        result.report = executePlan(plan, view, sink, progress, &mHistory,
                                    mOptions.incremental ? &mCache : nullptr);
    } catch (...) {
        mHistory = mHistoryBefore;  // a run that did not finish leaves no history behind
        throw;
    }
    result.input = minus(capture.inputSeconds(), before);
    result.capture = dynamic_cast<io::CaptureSource*>(kept.capture.get());
    return result;
}

FrameReport FrameDriver::runApart(const Plan& plan, int frame, FrameSink& sink, int64_t seed,
                                  const ProgressFn& progress) {
    FrameView view(source(frame), true, seed);
    return executePlan(plan, view, sink, progress);
}

}  // namespace fp::app
