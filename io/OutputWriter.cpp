#include "io/OutputWriter.h"

#include <algorithm>

#include "io/FramePattern.h"
#include "io/PngWriter.h"
#include "io/SafeFiles.h"
#include "foundation/Error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <chrono>
#include <functional>
#include <cmath>
#include <filesystem>

namespace fp::io {

namespace fs = std::filesystem;

std::string OutputWriter::dumpDir() const {
    return mOptions.dumpDir.empty() ? (fs::path(mOptions.outputDir) / "dump").string()
                                    : mOptions.dumpDir;
}

std::string OutputWriter::pathFor(const OutputDesc& output, int64_t frame) const {
    const std::string dir = output.isDump ? dumpDir() : mOptions.outputDir;
    std::string file = FramePattern(output.file).path(int(frame));
    // Dumps of a sequence get the frame number so frames do not overwrite each other.
    if (output.isDump) file = fs::path(file).stem().string() + fmt::format(".{:04d}.exr", frame);
    return (fs::path(dir) / file).lexically_normal().string();
}

namespace {
// docs/design.md, Numerics and determinism: no NaN reaches a file. A NaN (or an infinite colour; +inf is sky in depth-like data)
// here is a pass's fault: the frame fails naming it instead of writing the pixels.
void checkFinite(const OutputLayer& layer, const std::string& path, int64_t frame) {
    for (int m = 0; m < layer.texture->mipCount(); ++m) {
        const Image& img = layer.texture->mip(m);
        const bool color = layer.kind == PortKind::Color;
        const uint64_t bad = tbb::parallel_reduce(
            tbb::blocked_range<int>(0, img.height()), uint64_t(0),
            [&](const tbb::blocked_range<int>& rows, uint64_t count) {
                for (int c = 0; c < img.channelCount(); ++c)
                    for (int y = rows.begin(); y < rows.end(); ++y) {
                        const float* row = img.plane(c).row(y);
                        for (int x = 0; x < img.width(); ++x)
                            count += std::isnan(row[x]) || (color && std::isinf(row[x]));
                    }
                return count;
            },
            std::plus<uint64_t>());
        if (bad > 0)
            throw Error(fmt::format("{}: frame {}: '{}' holds {} NaN{} value(s){}; not written",
                                    path, frame, layer.name, bad,
                                    layer.kind == PortKind::Color ? "/Inf" : "",
                                    m ? fmt::format(" (mip {})", m) : ""));
    }
}
}  // namespace

OutputWriter::WrittenFile OutputWriter::writeFile(const OutputDesc& output,
                                                  const std::vector<OutputLayer>& layers,
                                                  const FrameInfo& frame) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    WrittenFile file{pathFor(output, frame.number)};
    const std::string& path = file.path;
    for (const auto& l : layers) checkFinite(l, path, frame.number);
    std::error_code ec;
    for (const auto& in : mOptions.protectedPaths)
        if (fs::exists(path) && fs::equivalent(path, in, ec))
            throw Error(fmt::format("{}: refusing to overwrite an input of this run", path));
    // Encoded in memory, then written: the two times apart.
    auto commit = [&](std::string_view bytes) {
        const auto encoded = Clock::now();
        writeFileAtomically(path, bytes, false);
        file.encodeSeconds = std::chrono::duration<double>(encoded - start).count();
        file.writeSeconds = std::chrono::duration<double>(Clock::now() - encoded).count();
        const std::lock_guard<std::mutex> lock(mMutex);
        mWritten.push_back(path);
        return file;
    };
    if (fs::path(path).extension() == ".png")
        return commit(encodePng(layers.front().texture->image(), mOptions.pngLevel, path));
    ExrMetadata meta;
    if (frame.hasCamera) meta.camera = frame.camera;
    meta.frame = frame.number;
    meta.strings["framepass:software"] = "framepass";
    std::vector<ExrPart> parts;
    auto half = [&](const OutputLayer& l) { return l.kind == PortKind::Color && mOptions.halfColor; };
    bool anyMips = false;
    for (const auto& l : layers) anyMips |= l.texture->mipCount() > 1;
    if (!anyMips) {
        // Layers of one size share a part; one traced at a lower resolution (SSGI's half
        // resolution, a ray-traced pass's screen percentage) goes to a part of its size, named
        // after its first layer. The largest part comes first, as "rgba": the file's display
        // window is the frame's.
        for (const auto& l : layers) {
            const Image& img = l.texture->image();
            auto part = std::find_if(parts.begin(), parts.end(), [&](const ExrPart& p) {
                return p.layers.front().image->width() == img.width() &&
                       p.layers.front().image->height() == img.height();
            });
            if (part == parts.end()) {
                parts.push_back({l.name, {}});
                part = parts.end() - 1;
            }
            part->layers.push_back({l.name, &img, half(l)});
        }
        auto area = [](const ExrPart& p) {
            return std::size_t(p.layers.front().image->width()) * p.layers.front().image->height();
        };
        std::stable_sort(parts.begin(), parts.end(),
                         [&](const ExrPart& a, const ExrPart& b) { return area(a) > area(b); });
        parts.front().name = "rgba";
    } else {
        // Mip levels differ in size, so each gets a part of its own: "<layer>.mip<k>".
        for (const auto& l : layers)
            for (int m = 0; m < l.texture->mipCount(); ++m)
                parts.push_back({fmt::format("{}.mip{}", l.name, m),
                                 {{l.name, &l.texture->mip(m), half(l)}}});
    }
    const std::vector<char> bytes = encodeExr(path, parts, meta, mOptions.compression);
    return commit({bytes.data(), bytes.size()});
}

}  // namespace fp::io
