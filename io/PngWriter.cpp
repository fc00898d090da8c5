#include "io/PngWriter.h"

#include "io/SafeFiles.h"

#include "io/ExrWriter.h"
#include "foundation/Error.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <unistd.h>

namespace fp::io {

void writePng(const std::string& path, const Image& rgb) {
    FP_CHECK(rgb.channelCount() >= 3, "{}: a PNG preview needs 3 channels", path);
    const int w = rgb.width(), h = rgb.height();
    std::vector<unsigned char> pixels(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = std::clamp(rgb.plane(c).at(x, y), 0.0f, 1.0f);
                pixels[(std::size_t(y) * w + x) * 3 + c] = (unsigned char)std::lround(v * 255.0f);
            }
    createParentFolder(path);
    const std::string tmp = temporaryPathFor(path);
    const InFlightTemporary inFlight(tmp);
    auto out = OIIO::ImageOutput::create("png");
    FP_CHECK(out, "{}: OpenImageIO has no PNG writer", path);
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) ||
        !out->close()) {
        removeTemporary(tmp);
        throw Error(fmt::format("{}: could not write PNG: {}", path, out->geterror()));
    }
    commitFile(tmp, path);
}

}  // namespace fp::io

namespace fp::io {

std::string encodePng(const Image& rgb) {
    // OpenImageIO writes through a file; a private temporary keeps this simple and portable.
    const auto dir = std::filesystem::temp_directory_path();
    const std::string path =
        (dir / fmt::format("framepass-{}-{}.png", ::getpid(), static_cast<const void*>(&rgb))).string();
    writePng(path, rgb);
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    std::filesystem::remove(path);
    return bytes;
}

}  // namespace fp::io
