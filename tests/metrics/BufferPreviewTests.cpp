// framepass sheet's classification and ranges on hand-made layers whose answers are worked out
// by hand: which kind each layer is, the range printed on its tile, and the colours it maps to.
#include "metrics/BufferPreview.h"

#include <doctest/doctest.h>

#include <algorithm>

#include <cmath>
#include <limits>

using namespace fp;

namespace {
Image oneChannel(std::initializer_list<float> values, int w, int h, const char* name = "Y") {
    Image img(w, h, {name});
    auto it = values.begin();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.plane(0).at(x, y) = *it++;
    return img;
}

std::array<float, 3> rgbAt(const Image& img, int x, int y) {
    return {img.plane(0).at(x, y), img.plane(1).at(x, y), img.plane(2).at(x, y)};
}

using S = std::vector<std::string>;
}  // namespace

TEST_SUITE("buffer preview") {
    TEST_CASE("layers are classified by buffer name first, then by their channels") {
        // Canonical semantic buffers: kind Color → colour, the depths, the normal, the ids, the
        // rest.
        CHECK(classifyLayer({"SceneColor", S{"R", "G", "B"}, "SceneColor"}, nullptr) ==
              PreviewKind::Color);
        CHECK(classifyLayer({"BaseColor", S{"R", "G", "B"}, ""}, nullptr) == PreviewKind::Color);
        CHECK(classifyLayer({"SceneDepth", S{"Z"}, "SceneDepth"}, nullptr) == PreviewKind::Depth);
        CHECK(classifyLayer({"PrevSceneDepth", S{"Z"}, ""}, nullptr) == PreviewKind::Depth);
        CHECK(classifyLayer({"WorldNormal", S{"X", "Y", "Z"}, ""}, nullptr) == PreviewKind::Normal);
        CHECK(classifyLayer({"ShadingModel", S{"Y"}, ""}, nullptr) == PreviewKind::Id);
        CHECK(classifyLayer({"InstanceId", S{"Y"}, ""}, nullptr) == PreviewKind::Id);
        CHECK(classifyLayer({"Velocity", S{"X", "Y"}, ""}, nullptr) == PreviewKind::Data);
        CHECK(classifyLayer({"CustomData", S{"R", "G", "B", "A"}, ""}, nullptr) ==
              PreviewKind::Data);
        // The profile's buffer wins over the file's layer name (a Blender depth pass).
        CHECK(classifyLayer({"ViewLayer.Depth", S{"Z"}, "SceneDepth"}, nullptr) ==
              PreviewKind::Depth);
        CHECK(classifyLayer({"ViewLayer.Normal", S{"X", "Y", "Z"}, "WorldNormal"}, nullptr) ==
              PreviewKind::Normal);

        // Not a semantic buffer: channel suffixes and values decide.
        CHECK(classifyLayer(
                  {"Truth.DiffuseIndirectFull", S{"R", "G", "B"}, "Truth.DiffuseIndirectFull"},
                  nullptr) == PreviewKind::Color);
        CHECK(classifyLayer({"", S{"R", "G", "B", "A"}, ""}, nullptr) == PreviewKind::Color);
        CHECK(classifyLayer({"Truth.DiffuseIndirectFull.StdErr", S{"R", "G", "B"}, ""}, nullptr) ==
              PreviewKind::Data);
        CHECK(classifyLayer({"Truth.AO", S{"Y"}, ""}, nullptr) == PreviewKind::Data);
        CHECK(classifyLayer({"hzb.furthest", S{"Z"}, ""}, nullptr) == PreviewKind::Depth);
        CHECK(classifyLayer({"my.linearDepth", S{"Y"}, ""}, nullptr) == PreviewKind::Depth);
        CHECK(classifyLayer({"cryptoId", S{"Y"}, "", true}, nullptr) == PreviewKind::Id);

        // X Y Z is a normal only when its values are those of unit vectors.
        Image unit(2, 1, {"X", "Y", "Z"});
        unit.plane(0).at(0, 0) = -1.0f;
        unit.plane(2).at(1, 0) = 0.7f;
        CHECK(classifyLayer({"bent", S{"X", "Y", "Z"}, ""}, &unit) == PreviewKind::Normal);
        unit.plane(1).at(1, 0) = 3.5f;  // a position, not a direction
        CHECK(classifyLayer({"bent", S{"X", "Y", "Z"}, ""}, &unit) == PreviewKind::Data);
        CHECK(classifyLayer({"bentNormal", S{"X", "Y", "Z"}, ""}, &unit) == PreviewKind::Normal);
    }

    TEST_CASE("depth: log grey between its finite positive min and max, sky in its own colour") {
        const float inf = std::numeric_limits<float>::infinity();
        // 10, √(10·1000) = 100 (halfway in log), 1000, and sky.
        const Image depth = oneChannel({10.0f, 100.0f, 1000.0f, inf}, 4, 1, "Z");
        const PreviewRange r = previewRange(depth, PreviewKind::Depth);
        REQUIRE(r.valid);
        CHECK(r.min == 10.0f);
        CHECK(r.max == 1000.0f);
        CHECK(r.logarithmic);
        CHECK(r.skyPixels == 1);
        CHECK(previewRangeLabel(PreviewKind::Depth, r) == "depth 10..1000 log, 1 sky");

        const Image rgb = previewData(depth, PreviewKind::Depth, r);
        CHECK(rgbAt(rgb, 0, 0) == std::array<float, 3>{0.0f, 0.0f, 0.0f});
        CHECK(rgb.plane(0).at(1, 0) == doctest::Approx(0.5f).epsilon(1e-6));
        CHECK(rgb.plane(2).at(1, 0) == rgb.plane(0).at(1, 0));  // grey
        CHECK(rgbAt(rgb, 2, 0) == std::array<float, 3>{1.0f, 1.0f, 1.0f});
        CHECK(rgbAt(rgb, 3, 0) == kSkyColor);

        // The label's figures: three significant digits, as the issue's "depth 12.3..845 log".
        const Image scene = oneChannel({12.34f, 845.2f}, 2, 1, "Z");
        CHECK(previewRangeLabel(PreviewKind::Depth, previewRange(scene, PreviewKind::Depth)) ==
              "depth 12.3..845 log");
        // All sky: no range, every pixel the sky colour.
        const Image sky = oneChannel({inf, -1.0f}, 2, 1, "Z");
        const PreviewRange rs = previewRange(sky, PreviewKind::Depth);
        CHECK_FALSE(rs.valid);
        CHECK(rs.skyPixels == 2);
        CHECK(rgbAt(previewData(sky, PreviewKind::Depth, rs), 1, 0) == kSkyColor);
    }

    TEST_CASE("data: linear from min (black) to max (white); NaN/Inf counted and marked") {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        const Image ao = oneChannel({0.25f, 0.5f, 1.0f, nan}, 4, 1);
        const PreviewRange r = previewRange(ao, PreviewKind::Data);
        CHECK(r.min == 0.25f);
        CHECK(r.max == 1.0f);
        CHECK_FALSE(r.logarithmic);
        CHECK(r.nonFinite == 1);
        CHECK(previewRangeLabel(PreviewKind::Data, r) == "0.25..1, 1 NaN/Inf");
        const Image rgb = previewData(ao, PreviewKind::Data, r);
        CHECK(rgbAt(rgb, 0, 0) == std::array<float, 3>{0.0f, 0.0f, 0.0f});
        CHECK(rgb.plane(1).at(1, 0) == doctest::Approx(1.0f / 3.0f));
        CHECK(rgbAt(rgb, 2, 0) == std::array<float, 3>{1.0f, 1.0f, 1.0f});
        CHECK(rgbAt(rgb, 3, 0) == kInvalidColor);

        // Two channels (velocity): one range over both, shown as R and G with a black B.
        Image velocity(1, 1, {"X", "Y"});
        velocity.plane(0).at(0, 0) = -2.0f;
        velocity.plane(1).at(0, 0) = 2.0f;
        const PreviewRange rv = previewRange(velocity, PreviewKind::Data);
        CHECK(previewRangeLabel(PreviewKind::Data, rv) == "-2..2");
        CHECK(rgbAt(previewData(velocity, PreviewKind::Data, rv), 0, 0) ==
              std::array<float, 3>{0.0f, 1.0f, 0.0f});
        // A constant layer says so and shows mid-grey.
        const Image flat = oneChannel({1.0f, 1.0f}, 2, 1);
        const PreviewRange rf = previewRange(flat, PreviewKind::Data);
        CHECK(previewRangeLabel(PreviewKind::Data, rf) == "constant 1");
        CHECK(previewData(flat, PreviewKind::Data, rf).plane(0).at(1, 0) == 0.5f);
        // Rounding noise around 0 at one end of a range reads as 0.
        const Image motion = oneChannel({-3.35f, 7.1e-15f}, 2, 1);
        CHECK(previewRangeLabel(PreviewKind::Data, previewRange(motion, PreviewKind::Data)) ==
              "-3.35..0");
    }

    TEST_CASE("normals show as n/2 + 1/2; ids as a false colour per value, 0 black") {
        Image n(1, 1, {"X", "Y", "Z"});
        n.plane(0).at(0, 0) = -1.0f;
        n.plane(1).at(0, 0) = 0.0f;
        n.plane(2).at(0, 0) = 1.0f;
        const PreviewRange rn = previewRange(n, PreviewKind::Normal);
        CHECK(previewRangeLabel(PreviewKind::Normal, rn) == "normal -1..1");
        CHECK(rgbAt(previewData(n, PreviewKind::Normal, rn), 0, 0) ==
              std::array<float, 3>{0.0f, 0.5f, 1.0f});

        const Image ids = oneChannel({0.0f, 1.0f, 2.0f, 1.0f}, 4, 1);
        const PreviewRange ri = previewRange(ids, PreviewKind::Id);
        CHECK(previewRangeLabel(PreviewKind::Id, ri) == "id 0..2");
        const Image rgb = previewData(ids, PreviewKind::Id, ri);
        CHECK(rgbAt(rgb, 0, 0) == std::array<float, 3>{0.0f, 0.0f, 0.0f});
        CHECK(rgbAt(rgb, 1, 0) == idColor(1));
        CHECK(rgbAt(rgb, 3, 0) == rgbAt(rgb, 1, 0));  // the same id, the same colour
        CHECK(rgbAt(rgb, 1, 0) != rgbAt(rgb, 2, 0));  // neighbouring ids differ
        for (uint32_t id = 1; id < 64; ++id) {
            const auto c = idColor(id);
            CHECK(std::max({c[0], c[1], c[2]}) >= 0.2f);  // never mistaken for 0
        }
    }

    TEST_CASE("colour layers get no range: the OCIO transform shows them") {
        const Image c(2, 2, {"R", "G", "B"}, 0.5f);
        const PreviewRange r = previewRange(c, PreviewKind::Color);
        CHECK_FALSE(r.valid);
        CHECK(previewRangeLabel(PreviewKind::Color, r) == "colour (OCIO)");
        CHECK(std::string(previewKindName(PreviewKind::Color)) == "colour");
        CHECK(std::string(previewKindName(PreviewKind::Depth)) == "depth");
    }

}  // TEST_SUITE
