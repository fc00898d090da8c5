#include "io/ExrReader.h"

#include "foundation/Error.h"
#include "foundation/Limits.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStdIO.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>

namespace fp::io {

namespace {

// The size a header declares is checked before OpenEXR sees the file: OpenEXR allocates what an
// attribute or a data window claims, so a 4 KB file claiming a 2 GB string, or a 100000² image,
// would take gigabytes before any check. This walks the header(s) (OpenEXR file layout: magic,
// version flags, then per part name\0 type\0 int32 size, value..., ended by an empty name;
// multi-part files end the list of headers with an empty header) without reading pixels.
void checkImageSize(const std::string& path, int64_t width, int64_t height) {
    if (width <= 0 || height <= 0 || width > limits::kMaxImageDimension ||
        height > limits::kMaxImageDimension || width * height > limits::kMaxImagePixels)
        throw Error(fmt::format("{}: the image is {}×{}; framepass reads at most {} pixels a side "
                                "and {} pixels in all (the limit)",
                                path, width, height, limits::kMaxImageDimension,
                                limits::kMaxImagePixels));
}

void checkExrHeaders(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(fmt::format("{}: cannot open", path));
    in.seekg(0, std::ios::end);
    const int64_t fileSize = in.tellg();
    in.seekg(0);
    auto fail = [&](const std::string& what) {
        throw Error(fmt::format("{}: not a readable OpenEXR file ({})", path, what));
    };
    auto readInt = [&](int32_t& v) {
        unsigned char b[4];
        if (!in.read(reinterpret_cast<char*>(b), 4)) fail("the header is truncated");
        v = int32_t(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 |
                    uint32_t(b[3]) << 24);
    };
    auto readName = [&](std::string& s) {
        s.clear();
        for (char c; in.get(c);) {
            if (c == '\0') return;
            if (s.size() >= 255) fail("a header name is longer than 255 characters");
            s += c;
        }
        fail("the header is truncated");
    };
    int32_t magic = 0, version = 0;
    readInt(magic);
    if (magic != 20000630) fail("no OpenEXR magic number");
    readInt(version);
    const bool multiPart = version & 0x1000;
    for (int part = 0;; ++part) {
        if (part >= 4096) fail("more than 4096 parts");
        std::string name, type;
        int attributes = 0;
        for (;; ++attributes) {
            readName(name);
            if (name.empty()) break;
            readName(type);
            int32_t size = 0;
            readInt(size);
            const int64_t left = fileSize - int64_t(in.tellg());
            if (size < 0 || size > left || size > limits::kMaxExrAttributeBytes)
                throw Error(fmt::format("{}: header attribute '{}' ({}) claims {} bytes; the file "
                                        "has {} after it and framepass reads at most {} (the "
                                        "limit)",
                                        path, name, type, size, left,
                                        limits::kMaxExrAttributeBytes));
            if (name == "dataWindow" && type == "box2i" && size == 16) {
                int32_t b[4];
                for (auto& v : b) readInt(v);
                checkImageSize(path, int64_t(b[2]) - b[0] + 1, int64_t(b[3]) - b[1] + 1);
            } else if (name == "chunkCount" && type == "int" && size == 4) {
                int32_t chunks = 0;
                readInt(chunks);
                if (chunks < 0 || chunks > limits::kMaxImagePixels)
                    fail(fmt::format("chunkCount {} is out of range", chunks));
            } else {
                in.seekg(size, std::ios::cur);
            }
        }
        // A multi-part file's list of headers ends with an empty header.
        if (!multiPart || attributes == 0) break;
    }
}

// The file as OpenEXR reads it, timing each read: the bytes' arrival apart from their decoding.
// OpenEXR's worker threads may read while another decodes, hence the atomic count.
class TimedFileStream final : public Imf::StdIFStream {
public:
    explicit TimedFileStream(const std::string& path) : Imf::StdIFStream(path.c_str()) {}
    bool read(char c[], int n) override {
        const auto t0 = std::chrono::steady_clock::now();
        const bool more = Imf::StdIFStream::read(c, n);
        mNanoseconds += std::chrono::duration_cast<std::chrono::nanoseconds>(
                            std::chrono::steady_clock::now() - t0)
                            .count();
        return more;
    }
    double seconds() const { return double(mNanoseconds.load()) * 1e-9; }

private:
    std::atomic<int64_t> mNanoseconds{0};
};

}  // namespace

double ExrReader::fileSeconds() const {
    return static_cast<const TimedFileStream&>(*mStream).seconds();
}

ExrReader::ExrReader(const std::string& path) : mPath(path) {
    if (!std::filesystem::exists(path)) throw Error(fmt::format("{}: no such file", path));
    if (std::filesystem::is_directory(path))
        throw Error(fmt::format("{}: is a folder, not an EXR file", path));
    checkExrHeaders(path);
    try {
        mStream = std::make_unique<TimedFileStream>(path);
        mFile = std::make_unique<Imf::MultiPartInputFile>(*mStream);
    } catch (const std::exception& e) {
        throw Error(fmt::format("{}: not a readable OpenEXR file ({})", path, e.what()));
    }
    for (int p = 0; p < mFile->parts(); ++p) {
        const Imf::Header& h = mFile->header(p);
        if (h.hasType() && h.type() != Imf::SCANLINEIMAGE && h.type() != Imf::TILEDIMAGE)
            throw Error(fmt::format("{}: part {} is a deep image, which framepass does not read",
                                    path, p));
        const auto dw = h.dataWindow();
        checkImageSize(path, int64_t(dw.max.x) - dw.min.x + 1, int64_t(dw.max.y) - dw.min.y + 1);
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
    return readRows(found, names, 0, size.height);
}

Image ExrReader::readRows(const std::vector<const ExrChannel*>& found,
                          const std::vector<std::string>& names, int firstRow, int rows) {
    const Extent whole = found.empty() ? mExtent : mPartExtents[found.front()->part];
    FP_CHECK(firstRow >= 0 && rows >= 0 && firstRow + rows <= whole.height,
             "{}: rows {}–{} of a part {} rows high", mPath, firstRow, firstRow + rows - 1,
             whole.height);
    const Extent size{whole.width, rows};
    std::vector<std::string> fileChannels;
    for (const ExrChannel* ch : found) {
        fileChannels.push_back(ch->name);
        const Extent e = mPartExtents[ch->part];
        FP_CHECK(e == whole, "{}: channel '{}' (part {}) is {}×{}, the others are {}×{}", mPath,
                 ch->name, ch->part, e.width, e.height, whole.width, whole.height);
    }
    Image image(size.width, size.height, names);
    std::map<int, Imf::FrameBuffer> perPart;
    std::map<int, int> partFirstRow;  // in each part's absolute row numbers
    for (std::size_t i = 0; i < found.size(); ++i) {
        const ExrChannel* ch = found[i];
        const auto dw = mFile->header(ch->part).dataWindow();
        Plane& plane = image.plane(int(i));
        // OpenEXR addresses the slice by absolute pixel coordinates: shift the base pointer so
        // that the first row read (dataWindow.min.y + firstRow) lands on the plane's first row.
        partFirstRow[ch->part] = dw.min.y + firstRow;
        char* base = reinterpret_cast<char*>(plane.row(0)) -
                     (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y + firstRow) * plane.stride()) *
                         std::ptrdiff_t(sizeof(float));
        perPart[ch->part].insert(ch->name, Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                                      plane.stride() * sizeof(float)));
        mReadLog.push_back(ch->name);
    }
    for (auto& [part, fb] : perPart) {
        try {
            Imf::InputPart in(*mFile, part);
            in.setFrameBuffer(fb);
            in.readPixels(partFirstRow[part], partFirstRow[part] + rows - 1);
        } catch (const std::exception& e) {
            throw Error(fmt::format("{}: could not read channels [{}]: {}", mPath,
                                    fmt::join(fileChannels, ", "), e.what()));
        }
    }
    return image;
}

}  // namespace fp::io
