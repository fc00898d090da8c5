#pragma once
// Labelled images for people: a contact sheet of display-referred tiles, each under a two-line
// label (`framepass sheet`), and a colour bar with its end values under a heat map (`compare
// --heatmap`, the bench report). Composited with OpenImageIO; text is drawn by its render_text
// with the DejaVu Sans font of Debian's fonts-dejavu-core.
#include "foundation/Image.h"

#include <string>
#include <vector>

namespace fp::io {

/// One tile: display-referred RGB in [0, 1] (any size; it is scaled to the tile) and its label.
struct SheetTile {
    std::string title;     //!< first label line: the layer ("SceneDepth", "a.exr: ssgi.ao")
    std::string subtitle;  //!< second line: its range ("depth 12.3..845 log")
    Image rgb;
};

struct SheetLayout {
    static constexpr int kLabelHeight = 30;  //!< two 11-px lines above each tile's image
    int columns = 1, rows = 1;
    int tileWidth = 0, tileHeight = 0;  //!< of the image part of a tile
    int cellHeight() const { return kLabelHeight + tileHeight; }
    int width() const { return columns * tileWidth; }
    int height() const { return rows * cellHeight(); }
};

/// `count` tiles of images `tileWidth` wide and `tileHeight` high in `columns` columns (0 = the
/// smallest square-ish grid: ⌈√count⌉), rows as needed, no gaps. Throws fp::UsageError for
/// non-positive sizes or no tiles.
SheetLayout sheetLayout(std::size_t count, int columns, int tileWidth, int tileHeight);

/// The height of an image `width` × `height` scaled to `tileWidth` wide (at least 1).
int scaledHeight(int width, int height, int tileWidth);

/// `rgb` scaled to `tileWidth` wide, keeping its aspect (box filter: data stays data, a few
/// pixels become blocks rather than blurs).
Image scaleToWidth(const Image& rgb, int tileWidth);

/// The sheet: tiles in reading order, each image at the top left of its cell under its label.
Image composeSheet(const std::vector<SheetTile>& tiles, const SheetLayout& layout);

/// Height of the band withColorBar adds.
inline constexpr int kColorBarHeight = 30;

/// `rgb` with a band below it: `ramp` (display RGB, N × 1: the colour map from its bottom to its
/// top) stretched across the width, `lo` under its left end, `hi` under its right end and
/// `title` between them.
Image withColorBar(const Image& rgb,
                   const Image& ramp,
                   const std::string& lo,
                   const std::string& hi,
                   const std::string& title);

}  // namespace fp::io
