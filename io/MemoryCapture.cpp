#include "io/MemoryCapture.h"

#include "foundation/Error.h"
#include "framework/SemanticBuffers.h"

#include <OpenEXR/ImfIntAttribute.h>
#include <fmt/ranges.h>

#include <algorithm>

namespace fp::io {

void MemoryCapture::note(const std::string& text) {
    if (std::find(mNotes.begin(), mNotes.end(), text) == mNotes.end()) mNotes.push_back(text);
}

std::vector<std::string> MemoryCapture::channelNames(const std::string& buffer, int channels) {
    const SemanticBuffer* sem = findSemanticBuffer(buffer);
    if (!sem && !isTruthBuffer(buffer)) {
        std::vector<std::string> known;
        for (const auto& b : semanticBuffers()) known.push_back(b.name);
        throw UsageError(fmt::format("'{}' is not a capture buffer: give one of {} or a Truth.* "
                                     "layer",
                                     buffer, fmt::join(known, ", ")));
    }
    if (sem && channels != int(sem->channels.size()))
        throw UsageError(fmt::format("buffer '{}' has {} channel{}; it has {} ({})", buffer,
                                     channels, channels == 1 ? "" : "s", sem->channels.size(),
                                     fmt::join(sem->channels, " ")));
    if (!sem && channels != 1 && channels != 3 && channels != 4)
        throw UsageError(fmt::format("truth layer '{}' has {} channels; a truth layer has 1, 3 "
                                     "or 4",
                                     buffer, channels));
    return sem ? sem->channels : truthSuffixes(channels);
}

void MemoryCapture::add(const std::string& buffer, Image image, bool sanitized) {
    try {
        channelNames(buffer, image.channelCount());
    } catch (const UsageError& e) {
        throw UsageError(fmt::format("{}: {}", mName, e.what()));
    }
    if (image.width() <= 0 || image.height() <= 0)
        throw UsageError(fmt::format("{}: buffer '{}' is empty ({}×{})", mName, buffer,
                                     image.width(), image.height()));
    const Extent size{image.width(), image.height()};
    if (mBuffers.empty()) mExtent = size;
    else if (!(size == mExtent))
        throw UsageError(fmt::format("{}: buffer '{}' is {}×{}, but '{}' is {}×{}: the buffers "
                                     "of a capture are one size",
                                     mName, buffer, size.width, size.height,
                                     mBuffers.begin()->first, mExtent.width, mExtent.height));
    if (!sanitized) {
        const SanitizeCounts counts = sanitizeBuffer(buffer, image);
        if (counts.total() > 0)
            note(fmt::format("{}: {} non-finite (or, for depth, ≤ 0), {} negative and {} non-unit "
                             "values replaced as a run replaces them",
                             buffer, counts.nonFinite, counts.negative, counts.nonUnitNormals));
        mSanitized += counts;
    }
    mBuffers[buffer] = std::move(image);
}

std::set<std::string> MemoryCapture::availableBuffers() const {
    std::set<std::string> out;
    for (const auto& [name, image] : mBuffers) out.insert(name);
    return out;
}

std::map<std::string, int> MemoryCapture::truthChannels() const {
    std::map<std::string, int> out;
    for (const auto& [name, image] : mBuffers)
        if (isTruthBuffer(name)) out[name] = image.channelCount();
    return out;
}

MemoryCapture readCapture(const std::string& path, const CaptureProfile& profile) {
    CaptureSource::Options options;
    options.path = path;
    CaptureSource source(options, profile);
    CaptureFiles& files = source.files();
    const auto* frameAttr =
        files.primary().header().findTypedAttribute<Imf::IntAttribute>("framepass:frame");
    MemoryCapture capture(files.capturePath(), frameAttr ? frameAttr->value() : 1);
    const std::map<std::string, int> truth = files.truthChannels();
    for (const auto& buffer : files.availableBuffers()) {
        const BufferMapping* m = files.mappingFor(buffer);
        if (m && !m->previousFrame.empty()) continue;  // frame N−1's file, not this one
        const SemanticBuffer* sem = findSemanticBuffer(buffer);
        const int channels = sem ? int(sem->channels.size()) : truth.at(buffer);
        capture.add(buffer, source.loadBuffer(buffer, channels).image(), true);
    }
    const FrameInfo info = source.frameInfo();
    if (info.hasCamera) capture.setCamera(info.camera);
    for (const auto& n : source.notes()) capture.note(n);
    for (const auto& w : files.warnings()) capture.note(w);
    return capture;
}

MemoryCaptureSource::MemoryCaptureSource(std::shared_ptr<const MemoryCapture> capture,
                                         CaptureOptions options)
    : SceneBackedSource(std::move(options)), mCapture(std::move(capture)) {}

FrameInfo MemoryCaptureSource::frameInfo() {
    FrameInfo info;
    info.number = mCapture->frame();
    info.extent = mCapture->extent();
    info.firstInSequence = mOptions.firstInSequence;
    if (mCapture->camera()) {
        info.camera = *mCapture->camera();
        info.hasCamera = true;
    }
    return info;
}

Texture MemoryCaptureSource::loadBuffer(const std::string& buffer, int channels) {
    const auto& buffers = mCapture->buffers();
    auto it = buffers.find(buffer);
    FP_CHECK(it != buffers.end(), "{}: the capture has no '{}'", mCapture->name(), buffer);
    const Image& image = it->second;
    if (image.channelCount() == channels) return Texture(image);  // shares the pixels
    FP_CHECK(channels < image.channelCount(), "{}: '{}' has {} channels, {} are read",
             mCapture->name(), buffer, image.channelCount(), channels);
    // A Truth layer read narrower than it was given (RGBA read as RGB): its first channels.
    std::vector<std::string> names(image.channels().begin(), image.channels().begin() + channels);
    Image narrower(image.width(), image.height(), names);
    for (int c = 0; c < channels; ++c)
        for (int y = 0; y < image.height(); ++y)
            std::copy_n(image.plane(c).row(y), image.width(), narrower.plane(c).row(y));
    return Texture(std::move(narrower));
}

}  // namespace fp::io
