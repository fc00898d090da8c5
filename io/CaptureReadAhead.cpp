#include "io/CaptureReadAhead.h"

#include <algorithm>

namespace fp::io {

CaptureReadAhead::~CaptureReadAhead() {
    for (Pending& p : mPending) stop(p);
}

void CaptureReadAhead::stop(Pending& p) {
    *p.cancelled = true;
    p.read.wait();
}

void CaptureReadAhead::start(CaptureOptions options, const CaptureProfile& profile,
                             std::vector<CaptureRead> reads) {
    if (std::any_of(mPending.begin(), mPending.end(),
                    [&](const Pending& p) { return p.frame == options.frame; }))
        return;
    auto cancelled = std::make_shared<std::atomic<bool>>(false);
    const int64_t frame = options.frame;
    auto read = std::async(std::launch::async,
                           [cancelled, options = std::move(options), profile,
                            reads = std::move(reads)]() -> std::unique_ptr<CaptureSource> {
                               try {
                                   auto source = std::make_unique<CaptureSource>(options, profile);
                                   source->frameInfo();  // the header and camera, read once
                                   source->readAhead(reads, *cancelled);
                                   return source;
                               } catch (const std::exception&) {
                                   return nullptr;  // the frame opens it again and says why
                               }
                           });
    mPending.push_back({frame, std::move(cancelled), std::move(read)});
}

std::unique_ptr<CaptureSource> CaptureReadAhead::take(int64_t frame) {
    const auto it = std::find_if(mPending.begin(), mPending.end(),
                                 [&](const Pending& p) { return p.frame == frame; });
    // The reads started before this frame's (all of them when it has none) are not needed.
    for (auto p = mPending.begin(); p != it; ++p) stop(*p);
    mPending.erase(mPending.begin(), it);
    if (mPending.empty()) return nullptr;
    std::unique_ptr<CaptureSource> source = mPending.front().read.get();
    mPending.pop_front();
    return source;
}

}  // namespace fp::io
