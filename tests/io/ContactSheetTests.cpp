// The contact sheet's layout and compositing, and the colour bar under heat maps: sizes worked
// out by hand, tiles where the layout puts them, labels drawn, bar ends in the ramp's colours.
#include "io/ContactSheet.h"
#include "foundation/Error.h"

#include <doctest/doctest.h>

#include <algorithm>

using namespace fp;

namespace {
// Pixels of a region brighter than `level` in any channel (drawn text on the dark background).
int brightPixels(const Image& img, int x0, int y0, int x1, int y1, float level = 0.5f) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            if (std::max({img.plane(0).at(x, y), img.plane(1).at(x, y), img.plane(2).at(x, y)}) >
                level)
                ++n;
    return n;
}
}  // namespace

TEST_SUITE("contact sheet") {
    TEST_CASE("the layout: columns × tile width by rows × (label + tile height)") {
        // 17 tiles (a canonical capture's layers) default to ⌈√17⌉ = 5 columns, 4 rows.
        io::SheetLayout l = io::sheetLayout(17, 0, 64, 64);
        CHECK(l.columns == 5);
        CHECK(l.rows == 4);
        CHECK(l.width() == 5 * 64);
        CHECK(l.height() == 4 * (io::SheetLayout::kLabelHeight + 64));
        l = io::sheetLayout(17, 6, 100, 50);
        CHECK(l.rows == 3);
        CHECK(l.width() == 600);
        CHECK(l.height() == 3 * (io::SheetLayout::kLabelHeight + 50));
        // More columns than tiles: one row as wide as the tiles.
        l = io::sheetLayout(2, 8, 10, 10);
        CHECK(l.columns == 2);
        CHECK(l.rows == 1);
        CHECK_THROWS_AS(io::sheetLayout(0, 0, 10, 10), UsageError);
        CHECK_THROWS_AS(io::sheetLayout(3, 0, 0, 10), UsageError);
        // An image keeps its aspect: 640×360 at 256 wide is 144 high.
        CHECK(io::scaledHeight(640, 360, 256) == 144);
        CHECK(io::scaledHeight(1000, 1, 10) == 1);
    }

    TEST_CASE("tiles land in reading order under their labels") {
        std::vector<io::SheetTile> tiles;
        for (float v : {0.25f, 0.5f, 1.0f})
            tiles.push_back({"layer", "0..1", Image(32, 16, {"R", "G", "B"}, v)});
        const io::SheetLayout l = io::sheetLayout(tiles.size(), 2, 64, 32);
        const Image sheet = io::composeSheet(tiles, l);
        REQUIRE(sheet.width() == 128);
        REQUIRE(sheet.height() == 2 * (io::SheetLayout::kLabelHeight + 32));
        const int label = io::SheetLayout::kLabelHeight;
        // Scaled ×2 (box): the value survives exactly. Tile 2 starts the second row.
        CHECK(sheet.plane(0).at(10, label + 5) == doctest::Approx(0.25f));
        CHECK(sheet.plane(1).at(64 + 63, label + 31) == doctest::Approx(0.5f));
        CHECK(sheet.plane(2).at(0, label + 32 + label) == doctest::Approx(1.0f));
        // The empty fourth cell is background.
        CHECK(sheet.plane(0).at(100, label + 32 + label + 10) < 0.2f);
        // Each label band has text in it, and the text stays inside its own cell.
        CHECK(brightPixels(sheet, 0, 0, 64, label) > 20);
        CHECK(brightPixels(sheet, 64, 0, 128, label) > 20);
        CHECK(brightPixels(sheet, 64, label + 32, 128, 2 * label + 32) == 0);
    }

    TEST_CASE("a colour bar under an image: the ramp stretched across, its values printed") {
        const Image img(100, 20, {"R", "G", "B"}, 0.3f);
        Image ramp(2, 1, {"R", "G", "B"});
        ramp.plane(0).at(0, 0) = 0.1f;  // dark red at 0, green at the top
        ramp.plane(1).at(1, 0) = 0.9f;
        const Image out = io::withColorBar(img, ramp, "0", "0.0123", "|error|");
        REQUIRE(out.width() == 100);
        REQUIRE(out.height() == 20 + io::kColorBarHeight);
        CHECK(out.plane(0).at(50, 10) == doctest::Approx(0.3f));  // the image is untouched
        CHECK(out.plane(0).at(0, 25) == doctest::Approx(0.1f));
        CHECK(out.plane(1).at(0, 25) == 0.0f);
        CHECK(out.plane(1).at(99, 25) == doctest::Approx(0.9f));
        CHECK(brightPixels(out, 0, 34, 100, 50) > 20);  // the numbers
    }

}  // TEST_SUITE
