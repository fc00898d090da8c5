#include "io/ExrWriter.h"

#include "io/SafeFiles.h"

#include "io/CameraIO.h"
#include "foundation/Error.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <unistd.h>

namespace fp::io {

namespace fs = std::filesystem;

ExrCompression parseCompression(const std::string& name) {
    if (name == "zip") return ExrCompression::Zip;
    if (name == "none") return ExrCompression::None;
    if (name == "piz") return ExrCompression::Piz;
    if (name == "zips") return ExrCompression::Zips;
    throw UsageError(fmt::format("unknown EXR compression '{}' (zip, zips, piz, none; lossy "
                                 "codecs are refused because they damage data layers)",
                                 name));
}

std::string temporaryPathFor(const std::string& path) {
    const fs::path p(path);
    return (p.parent_path() / fmt::format(".{}.{}.tmp", p.filename().string(), ::getpid())).string();
}

void commitFile(const std::string& tmp, const std::string& path) {
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        removeTemporary(tmp);
        throw Error(fmt::format("{}: could not move the finished file into place: {}", path,
                                ec.message()));
    }
}

namespace {

Imf::Compression toImf(ExrCompression c) {
    switch (c) {
        case ExrCompression::None: return Imf::NO_COMPRESSION;
        case ExrCompression::Piz: return Imf::PIZ_COMPRESSION;
        case ExrCompression::Zips: return Imf::ZIPS_COMPRESSION;
        case ExrCompression::Zip: break;
    }
    return Imf::ZIP_COMPRESSION;
}

// The file OpenEXR writes, held in memory: OpenEXR seeks back to fill in the chunk offsets.
class MemoryStream final : public Imf::OStream {
public:
    MemoryStream() : Imf::OStream("memory") {}
    void write(const char c[], int n) override {
        if (mPosition + std::size_t(n) > mBytes.size()) mBytes.resize(mPosition + std::size_t(n));
        std::memcpy(mBytes.data() + mPosition, c, std::size_t(n));
        mPosition += std::size_t(n);
    }
    uint64_t tellp() override { return mPosition; }
    void seekp(uint64_t position) override { mPosition = position; }
    std::vector<char> take() { return std::move(mBytes); }

private:
    std::vector<char> mBytes;
    std::size_t mPosition = 0;
};

// Owns the pixel buffers (half conversions, or float planes referenced in place) of one part.
struct PartBuffers {
    Imf::Header header;
    Imf::FrameBuffer frameBuffer;
    std::vector<std::shared_ptr<void>> halves;
};

void buildPart(PartBuffers& pb, const ExrPart& part, const ExrMetadata& meta,
               ExrCompression compression, bool multiPart) {
    FP_CHECK(!part.layers.empty(), "EXR part '{}' has no layers", part.name);
    const int w = part.layers.front().image->width(), h = part.layers.front().image->height();
    // Parts of one file must share their display window: every part (mip) shows its pixels in
    // the window of the first, largest one, and has a data window of its own size.
    const int dw = part.displayWidth > 0 ? part.displayWidth : w;
    const int dh = part.displayHeight > 0 ? part.displayHeight : h;
    pb.header = Imf::Header(Imath::Box2i({0, 0}, {dw - 1, dh - 1}),
                            Imath::Box2i({0, 0}, {w - 1, h - 1}));
    pb.header.compression() = toImf(compression);
    if (multiPart) {
        pb.header.setName(part.name);
        pb.header.setType(Imf::SCANLINEIMAGE);
    }
    if (meta.camera) writeCameraAttributes(pb.header, *meta.camera);
    if (meta.frame) pb.header.insert("framepass:frame", Imf::IntAttribute(int(*meta.frame)));
    for (const auto& [k, v] : meta.strings) pb.header.insert(k, Imf::StringAttribute(v));
    for (const auto& layer : part.layers) {
        const Image& img = *layer.image;
        FP_CHECK(img.width() == w && img.height() == h,
                 "layer '{}' is {}×{} but its part is {}×{}", layer.name, img.width(), img.height(),
                 w, h);
        for (int c = 0; c < img.channelCount(); ++c) {
            const std::string name = layer.name.empty() ? img.channels()[c]
                                                        : layer.name + "." + img.channels()[c];
            const Plane& plane = img.plane(c);
            if (layer.half) {
                // From the pool images' blocks come from (foundation/Image.h): a sequence converts
                // the same sizes frame after frame.
                std::shared_ptr<void> buf = hostScratch(std::size_t(w) * h * sizeof(half));
                half* out = static_cast<half*>(buf.get());
                tbb::parallel_for(0, h, [&](int y) {
                    const float* row = plane.row(y);
                    for (int x = 0; x < w; ++x) {
                        float v = row[x];
                        // Saturate to half's range: an HDR 1e5 stays the largest finite half.
                        if (std::isfinite(v)) v = std::clamp(v, -65504.0f, 65504.0f);
                        out[std::size_t(y) * w + x] = half(v);
                    }
                });
                pb.header.channels().insert(name, Imf::Channel(Imf::HALF));
                pb.frameBuffer.insert(name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(out),
                                                       sizeof(half), sizeof(half) * w));
                pb.halves.push_back(std::move(buf));
            } else {
                pb.header.channels().insert(name, Imf::Channel(Imf::FLOAT));
                pb.frameBuffer.insert(
                    name, Imf::Slice(Imf::FLOAT,
                                     reinterpret_cast<char*>(const_cast<float*>(plane.row(0))),
                                     sizeof(float), plane.stride() * sizeof(float)));
            }
        }
    }
}

std::vector<char> encodeParts(const std::vector<ExrPart>& parts, const ExrMetadata& meta,
                              ExrCompression compression) {
    FP_CHECK(!parts.empty(), "nothing to encode");
    const bool multiPart = parts.size() > 1;
    std::vector<PartBuffers> buffers(parts.size());
    std::vector<ExrPart> sized = parts;
    for (auto& p : sized) {
        p.displayWidth = parts.front().layers.front().image->width();
        p.displayHeight = parts.front().layers.front().image->height();
    }
    for (std::size_t i = 0; i < parts.size(); ++i)
        buildPart(buffers[i], sized[i], meta, compression, multiPart);
    MemoryStream file;
    if (!multiPart) {
        Imf::OutputFile out(file, buffers[0].header);
        out.setFrameBuffer(buffers[0].frameBuffer);
        out.writePixels(buffers[0].header.dataWindow().max.y -
                        buffers[0].header.dataWindow().min.y + 1);
    } else {
        std::vector<Imf::Header> headers;
        for (const auto& b : buffers) headers.push_back(b.header);
        Imf::MultiPartOutputFile out(file, headers.data(), int(headers.size()));
        for (std::size_t i = 0; i < buffers.size(); ++i) {
            Imf::OutputPart part(out, int(i));
            part.setFrameBuffer(buffers[i].frameBuffer);
            const auto dw = buffers[i].header.dataWindow();
            part.writePixels(dw.max.y - dw.min.y + 1);
        }
    }
    return file.take();
}
}  // namespace

std::vector<char> encodeExr(const std::string& path, const std::vector<ExrPart>& parts,
                            const ExrMetadata& meta, ExrCompression compression) {
    try {
        return encodeParts(parts, meta, compression);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(fmt::format("{}: could not write: {}", path, e.what()));
    }
}

void writeExr(const std::string& path, const std::vector<ExrPart>& parts,
              const ExrMetadata& meta, ExrCompression compression) {
    const std::vector<char> bytes = encodeExr(path, parts, meta, compression);
    writeFileAtomically(path, {bytes.data(), bytes.size()}, false);
}

}  // namespace fp::io
