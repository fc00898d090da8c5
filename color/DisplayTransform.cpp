#include "color/DisplayTransform.h"

#include "foundation/Error.h"
#include "passes/display/DisplayKernel.h"
#include "foundation/Tiles.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace OCIO = OCIO_NAMESPACE;

DisplayTransform::DisplayTransform(const OCIO::ConstConfigRcPtr& config,
                                   const std::string& inputSpace, const std::string& display,
                                   const std::string& view, float exposureStops, bool colorManaged,
                                   std::optional<color::FilmParams> film)
    : mGain(std::exp2(exposureStops)) {
    if (!colorManaged) return;
    if (film) {
        mFilm = film;
        return;
    }
    try {
        const std::string d = display.empty() ? config->getDefaultDisplay() : display;
        const std::string v = view.empty() ? config->getDefaultView(d.c_str()) : view;
        auto transform = OCIO::DisplayViewTransform::Create();
        transform->setSrc(inputSpace.c_str());
        transform->setDisplay(d.c_str());
        transform->setView(v.c_str());
        mCpu = config->getProcessor(transform)->getDefaultCPUProcessor();
    } catch (const OCIO::Exception& e) {
        throw Error(fmt::format("OCIO display transform (space '{}', display '{}', view '{}'): {}",
                                inputSpace, display, view, e.what()));
    }
}

Image DisplayTransform::apply(const Image& src) const {
    Image dst(src.width(), src.height(), {"R", "G", "B"});
    apply(src, dst);
    return dst;
}

void DisplayTransform::apply(const Image& src, Image& dst) const {
    const int channels = src.channelCount();
    if (mFilm) {  // the display kernel's own pixel, as the GPU runs it
        display::Frame f{};
        f.channels = std::min(channels, 4);
        for (int c = 0; c < f.channels; ++c) f.src[c] = viewOf(src.plane(c));
        f.gain = mGain;
        f.film = true;
        f.filmParams = *mFilm;
        for (int c = 0; c < 3; ++c) f.dst[c] = spanOf(dst.plane(c));
        forEachTile(src.width(), src.height(), [&](const Tile& t) {
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) display::displayPixel(f, x, y);
        });
        return;
    }
    forEachTile(src.width(), src.height(), [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int c = 0; c < 3; ++c) {
                const int from = display::previewSource(c, channels);
                float* d = dst.plane(c).row(y);
                if (from < 0) {
                    std::fill(d + t.x0, d + t.x1, 0.0f);
                    continue;
                }
                const float* s = src.plane(from).row(y);
                for (int x = t.x0; x < t.x1; ++x)
                    d[x] = display::exposed(s[x], mGain);
            }
        if (mCpu) {
            const long w = t.x1 - t.x0, h = t.y1 - t.y0;
            const std::ptrdiff_t yStride = dst.plane(0).stride() * std::ptrdiff_t(sizeof(float));
            OCIO::PlanarImageDesc desc(dst.plane(0).row(t.y0) + t.x0, dst.plane(1).row(t.y0) + t.x0,
                                       dst.plane(2).row(t.y0) + t.x0, nullptr, w, h,
                                       OCIO::BIT_DEPTH_F32, sizeof(float), yStride);
            mCpu->apply(desc);
        }
        for (int c = 0; c < 3; ++c)
            for (int y = t.y0; y < t.y1; ++y) {
                float* d = dst.plane(c).row(y);
                for (int x = t.x0; x < t.x1; ++x) d[x] = std::clamp(d[x], 0.0f, 1.0f);
            }
    });
}

Image DisplayTransform::filmCube(const color::FilmParams& film, int size) {
    Image cube(size * size, size, {"R", "G", "B"});
    const auto value = [&](int i) {
        const float t = float(i) / float(size - 1);
        return std::exp2(kFilmCubeLog2Min + t * (kFilmCubeLog2Max - kFilmCubeLog2Min));
    };
    forEachTile(size * size, size, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const float in[3] = {value(x % size), value(x / size), value(y)};
                float toned[3];
                color::ue4FilmicTonemap(film, in, toned);
                for (int c = 0; c < 3; ++c)
                    cube.plane(c).at(x, y) = color::srgbEncode(std::min(toned[c], 1.0f));
            }
    });
    return cube;
}

std::optional<Image> DisplayTransform::halfLut() const {
    if (!mCpu || mCpu->hasChannelCrosstalk())
        return std::nullopt;
    Image lut(display::kHalfLutSize, 1, {"R", "G", "B"});
    for (int i = 0; i < display::kHalfLutSize; ++i) {
        // Infinities and NaNs are never looked up; they hold the largest finite half's value.
        const uint32_t magnitude = std::min<uint32_t>(uint32_t(i) & 0x7FFFu, display::kMaxFiniteHalf);
        const float v = display::halfValue(magnitude);
        for (int c = 0; c < 3; ++c)
            lut.plane(c).at(i, 0) = (i & 0x8000) ? -v : v;
    }
    OCIO::PlanarImageDesc desc(lut.plane(0).row(0), lut.plane(1).row(0), lut.plane(2).row(0),
                               nullptr, display::kHalfLutSize, 1);
    mCpu->apply(desc);
    return lut;
}

}  // namespace fp
