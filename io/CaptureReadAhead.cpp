#include "io/CaptureReadAhead.h"

namespace fp::io {

CaptureReadAhead::~CaptureReadAhead() {
    stop();
}

void CaptureReadAhead::stop() {
    if (!mRead.valid()) return;
    mCancelled = true;
    mRead.wait();
    mRead = {};
}

void CaptureReadAhead::start(CaptureOptions options, const CaptureProfile& profile,
                             std::vector<CaptureRead> reads) {
    stop();
    mCancelled = false;
    mFrame = options.frame;
    mRead = std::async(std::launch::async,
                       [this, options = std::move(options), profile,
                        reads = std::move(reads)]() -> std::unique_ptr<CaptureSource> {
                           try {
                               auto source = std::make_unique<CaptureSource>(options, profile);
                               source->frameInfo();  // the header and camera, read once
                               source->readAhead(reads, mCancelled);
                               return source;
                           } catch (const std::exception&) {
                               return nullptr;  // the frame opens it again and says why
                           }
                       });
}

std::unique_ptr<CaptureSource> CaptureReadAhead::take(int64_t frame) {
    if (!mRead.valid()) return nullptr;
    if (mFrame != frame) {
        stop();
        return nullptr;
    }
    auto source = mRead.get();
    mRead = {};
    return source;
}

}  // namespace fp::io
