#include "io/ExrReader.h"

#include "passes/core/Error.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfPartType.h>

#include <filesystem>
#include <map>

namespace fp::io {

ExrReader::ExrReader(const std::string& path) : mPath(path) {
    if (!std::filesystem::exists(path)) throw Error(fmt::format("{}: no such file", path));
    try {
        mFile = std::make_unique<Imf::MultiPartInputFile>(path.c_str());
    } catch (const std::exception& e) {
        throw Error(fmt::format("{}: not a readable OpenEXR file ({})", path, e.what()));
    }
    for (int p = 0; p < mFile->parts(); ++p) {
        const Imf::Header& h = mFile->header(p);
        if (h.hasType() && h.type() != Imf::SCANLINEIMAGE && h.type() != Imf::TILEDIMAGE)
            throw Error(fmt::format("{}: part {} is a deep image, which framepass does not read",
                                    path, p));
        const auto dw = h.dataWindow();
        const Extent e{dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1};
        if (p == 0) mExtent = e;
        mPartExtents.push_back(e);
        for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
            if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
                throw Error(fmt::format("{}: channel '{}' is subsampled, which is not supported",
                                        path, it.name()));
            mChannels.push_back({it.name(), p, it.channel().type});
        }
    }
}

ExrReader::~ExrReader() = default;

const ExrChannel* ExrReader::findChannel(const std::string& name) const {
    for (const auto& c : mChannels)
        if (c.name == name) return &c;
    return nullptr;
}

const Imf::Header& ExrReader::header(int part) const { return mFile->header(part); }
int ExrReader::partCount() const { return mFile->parts(); }

Image ExrReader::read(const std::vector<std::string>& fileChannels,
                      const std::vector<std::string>& names) {
    FP_CHECK(fileChannels.size() == names.size(), "{}: {} channels read into {} names", mPath,
             fileChannels.size(), names.size());
    std::vector<const ExrChannel*> found;
    for (const auto& name : fileChannels) {
        const ExrChannel* ch = findChannel(name);
        FP_CHECK(ch, "{}: no channel '{}'", mPath, name);
        found.push_back(ch);
    }
    return read(found, names);
}

Image ExrReader::read(const std::vector<const ExrChannel*>& found,
                      const std::vector<std::string>& names) {
    const Extent size = found.empty() ? mExtent : mPartExtents[found.front()->part];
    std::vector<std::string> fileChannels;
    for (const ExrChannel* ch : found) {
        fileChannels.push_back(ch->name);
        const Extent e = mPartExtents[ch->part];
        FP_CHECK(e == size, "{}: channel '{}' (part {}) is {}×{}, the others are {}×{}", mPath,
                 ch->name, ch->part, e.width, e.height, size.width, size.height);
    }
    Image image(size.width, size.height, names);
    std::map<int, Imf::FrameBuffer> perPart;
    for (std::size_t i = 0; i < found.size(); ++i) {
        const ExrChannel* ch = found[i];
        const auto dw = mFile->header(ch->part).dataWindow();
        Plane& plane = image.plane(int(i));
        // OpenEXR addresses the slice by absolute pixel coordinates: shift the base pointer so
        // that dataWindow.min lands on the first float of the plane.
        char* base = reinterpret_cast<char*>(plane.row(0)) -
                     (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * plane.stride()) *
                         std::ptrdiff_t(sizeof(float));
        perPart[ch->part].insert(ch->name, Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                                      plane.stride() * sizeof(float)));
        mReadLog.push_back(ch->name);
    }
    for (auto& [part, fb] : perPart) {
        try {
            Imf::InputPart in(*mFile, part);
            in.setFrameBuffer(fb);
            const auto dw = in.header().dataWindow();
            in.readPixels(dw.min.y, dw.max.y);
        } catch (const std::exception& e) {
            throw Error(fmt::format("{}: could not read channels [{}]: {}", mPath,
                                    fmt::join(fileChannels, ", "), e.what()));
        }
    }
    return image;
}

}  // namespace fp::io
