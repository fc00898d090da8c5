#include "io/PngWriter.h"

#include "io/SafeFiles.h"
#include "foundation/Error.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace fp::io {

namespace {
std::string encodePixels(const Image& rgb, int zlibLevel) {
    FP_CHECK(rgb.channelCount() >= 3, "a PNG preview needs 3 channels, the image has {}",
             rgb.channelCount());
    FP_CHECK(zlibLevel >= 0 && zlibLevel <= 9, "PNG compression level {} is not 0–9", zlibLevel);
    const int w = rgb.width(), h = rgb.height();
    std::vector<unsigned char> pixels(std::size_t(w) * h * 3);
    tbb::parallel_for(0, h, [&](int y) {
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = std::clamp(rgb.plane(c).at(x, y), 0.0f, 1.0f);
                pixels[(std::size_t(y) * w + x) * 3 + c] = (unsigned char)std::lround(v * 255.0f);
            }
    });
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput memory(bytes);
    auto out = OIIO::ImageOutput::create("png");
    FP_CHECK(out, "OpenImageIO has no PNG writer");
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("png:compressionLevel", zlibLevel);
    if (!out->set_ioproxy(&memory) || !out->open("memory.png", spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close())
        throw Error(fmt::format("could not encode a PNG: {}", out->geterror()));
    return std::string(bytes.begin(), bytes.end());
}
}  // namespace

std::string encodePng(const Image& rgb, int zlibLevel, const std::string& path) {
    if (path.empty()) return encodePixels(rgb, zlibLevel);
    try {
        return encodePixels(rgb, zlibLevel);
    } catch (const Error& e) {
        throw Error(fmt::format("{}: {}", path, e.what()));
    }
}

void writePng(const std::string& path, const Image& rgb, int zlibLevel) {
    writeFileAtomically(path, encodePng(rgb, zlibLevel, path), false);
}

}  // namespace fp::io
