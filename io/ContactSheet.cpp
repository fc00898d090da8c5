#include "io/ContactSheet.h"

#include "foundation/Error.h"

#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>

namespace fp::io {

namespace {

// Debian's fonts-dejavu-core; OpenImageIO finds it by name in the system font folders (its own
// default, DroidSans, is not packaged).
constexpr const char* kFont = "DejaVuSans";
constexpr int kFontSize = 11;
constexpr float kBackground = 0.12f;
constexpr float kTextColor[3] = {0.92f, 0.92f, 0.92f};

OIIO::ImageBuf toBuf(const Image& rgb) {
    const int w = rgb.width(), h = rgb.height();
    OIIO::ImageBuf buf(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
    std::vector<float> pixels(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                pixels[(std::size_t(y) * w + x) * 3 + c] = rgb.plane(c).at(x, y);
    buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, pixels.data());
    return buf;
}

Image fromBuf(const OIIO::ImageBuf& buf) {
    const int w = buf.spec().width, h = buf.spec().height;
    std::vector<float> pixels(std::size_t(w) * h * 3);
    buf.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, pixels.data());
    Image out(w, h, {"R", "G", "B"});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                out.plane(c).at(x, y) = pixels[(std::size_t(y) * w + x) * 3 + c];
    return out;
}

OIIO::ImageBuf blank(int w, int h) {
    OIIO::ImageBuf buf(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
    const float bg[3] = {kBackground, kBackground, kBackground};
    OIIO::ImageBufAlgo::fill(buf, bg);
    return buf;
}

// Text drawn into its own buffer of the size of `clip` and pasted there, so that a long label is
// cut at the edge of its tile instead of running into the next one (render_text's ROI does not
// clip the glyphs).
void text(OIIO::ImageBuf& buf,
          int x,
          int baseline,
          const std::string& s,
          OIIO::ROI clip,
          OIIO::ImageBufAlgo::TextAlignX align = OIIO::ImageBufAlgo::TextAlignX::Left) {
    if (s.empty())
        return;
    OIIO::ImageBuf box = blank(clip.width(), clip.height());
    std::vector<float> under(std::size_t(clip.width()) * clip.height() * 3);
    buf.get_pixels(clip, OIIO::TypeDesc::FLOAT, under.data());
    box.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, under.data());
    if (!OIIO::ImageBufAlgo::render_text(box, x - clip.xbegin, baseline - clip.ybegin, s, kFontSize,
                                         kFont, kTextColor, align,
                                         OIIO::ImageBufAlgo::TextAlignY::Baseline))
        throw Error(
            fmt::format("cannot draw the label '{}' with the {} font ({}); install "
                        "Debian's fonts-dejavu-core",
                        s, kFont, box.geterror()));
    OIIO::ImageBufAlgo::paste(buf, clip.xbegin, clip.ybegin, 0, 0, box);
}

}  // namespace

SheetLayout sheetLayout(std::size_t count, int columns, int tileWidth, int tileHeight) {
    if (count == 0)
        throw UsageError("a contact sheet needs at least one tile");
    if (tileWidth <= 0 || tileHeight <= 0 || columns < 0)
        throw UsageError(
            fmt::format("a contact sheet needs positive tile sizes and columns (got "
                        "{}×{}, {} columns)",
                        tileWidth, tileHeight, columns));
    SheetLayout l;
    l.columns = columns > 0 ? columns : int(std::ceil(std::sqrt(double(count))));
    l.columns = std::min<int>(l.columns, int(count));
    l.rows = int((count + std::size_t(l.columns) - 1) / std::size_t(l.columns));
    l.tileWidth = tileWidth;
    l.tileHeight = tileHeight;
    return l;
}

int scaledHeight(int width, int height, int tileWidth) {
    return std::max(1, int(std::lround(double(height) * tileWidth / std::max(width, 1))));
}

Image scaleToWidth(const Image& rgb, int tileWidth) {
    const int h = scaledHeight(rgb.width(), rgb.height(), tileWidth);
    if (rgb.width() == tileWidth && rgb.height() == h)
        return rgb;
    OIIO::ImageBuf scaled(OIIO::ImageSpec(tileWidth, h, 3, OIIO::TypeDesc::FLOAT));
    if (!OIIO::ImageBufAlgo::resize(scaled, toBuf(rgb), "box"))
        throw Error(
            fmt::format("cannot scale a tile to {}×{}: {}", tileWidth, h, scaled.geterror()));
    return fromBuf(scaled);
}

Image composeSheet(const std::vector<SheetTile>& tiles, const SheetLayout& layout) {
    OIIO::ImageBuf sheet = blank(layout.width(), layout.height());
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        const int x0 = int(i % std::size_t(layout.columns)) * layout.tileWidth;
        const int y0 = int(i / std::size_t(layout.columns)) * layout.cellHeight();
        const OIIO::ROI label(x0, x0 + layout.tileWidth, y0, y0 + SheetLayout::kLabelHeight, 0, 1,
                              0, 3);
        text(sheet, x0 + 3, y0 + 12, tiles[i].title, label);
        text(sheet, x0 + 3, y0 + 26, tiles[i].subtitle, label);
        const Image scaled = scaleToWidth(tiles[i].rgb, layout.tileWidth);
        // A taller image than the sheet's tiles (another file's aspect) is cut at its cell.
        const OIIO::ImageBuf src = toBuf(scaled);
        const OIIO::ROI part(0, layout.tileWidth, 0, std::min(scaled.height(), layout.tileHeight),
                             0, 1, 0, 3);
        OIIO::ImageBufAlgo::paste(sheet, x0, y0 + SheetLayout::kLabelHeight, 0, 0, src, part);
    }
    return fromBuf(sheet);
}

Image withColorBar(const Image& rgb,
                   const Image& ramp,
                   const std::string& lo,
                   const std::string& hi,
                   const std::string& title) {
    const int w = rgb.width(), h = rgb.height();
    OIIO::ImageBuf out = blank(w, h + kColorBarHeight);
    OIIO::ImageBufAlgo::paste(out, 0, 0, 0, 0, toBuf(rgb));
    const int n = ramp.width();
    for (int x = 0; x < w; ++x) {
        const int i = n > 1 && w > 1 ? int(std::lround(double(x) * (n - 1) / (w - 1))) : 0;
        const float c[3] = {ramp.plane(0).at(i, 0), ramp.plane(1).at(i, 0), ramp.plane(2).at(i, 0)};
        for (int y = h + 3; y < h + 13; ++y)
            out.setpixel(x, y, c, 3);
    }
    const OIIO::ROI band(0, w, h, h + kColorBarHeight, 0, 1, 0, 3);
    using Align = OIIO::ImageBufAlgo::TextAlignX;
    const int baseline = h + kColorBarHeight - 4;
    text(out, 1, baseline, lo, band, Align::Left);
    text(out, w - 2, baseline, hi, band, Align::Right);
    // The title only where it fits between the two values.
    auto width = [](const std::string& s) {
        const OIIO::ROI r = OIIO::ImageBufAlgo::text_size(s, kFontSize, kFont);
        return r.defined() ? r.width() : 0;
    };
    if (width(lo) + width(hi) + width(title) + 16 <= w)
        text(out, w / 2, baseline, title, band, Align::Center);
    return fromBuf(out);
}

}  // namespace fp::io
