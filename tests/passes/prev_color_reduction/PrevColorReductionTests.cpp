// prev_color_reduction: the reduced previous colour on flat frames, with and without leak-free
// weighting.
#include "passes/prev_color_reduction/PrevColorReductionPass.h"
#include "framework/Executor.h"
#include "framework/Planner.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace fp;

namespace {

// A frame whose every pixel sees a plane at depth `depth`, facing the camera.
test::MemorySource flatFrame(int w, int h, float depth, const Vec3f& prevColor, float prevDepth) {
    test::MemorySource src;
    src.info.extent = {w, h};
    src.info.camera.current = CameraView::lookAt({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 60.0, w, h, 10.0);
    src.info.camera.previous = src.info.camera.current;
    src.info.hasCamera = true;
    src.buffers["SceneDepth"] = Image(w, h, {"Z"}, depth);
    src.buffers["PrevSceneDepth"] = Image(w, h, {"Z"}, prevDepth);
    Image pc(w, h, {"R", "G", "B"});
    for (int c = 0; c < 3; ++c)
        pc.plane(c) = Plane(w, h, prevColor[c]);
    src.buffers["PrevSceneColor"] = pc;
    src.buffers["TAAHistory"] = pc;
    return src;
}

}  // namespace

TEST_SUITE("prev_color_reduction") {
    TEST_CASE("reduced previous colour: a static, matching surface keeps its colour at every mip") {
        const int w = 64, h = 64;
        auto src = flatFrame(w, h, 200.0f, {1.0f, 2.0f, 3.0f}, 200.0f);
        const Plan plan = test::planFor(
            {test::node("hzb"),
             test::node("prev_color_reduction", {}, {{"furthestHzb", "hzb.furthest"}})},
            {"prev_color_reduction.color", "prev_color_reduction.alpha"});
        CHECK(plan.captureReads.size() == 3);  // SceneDepth, PrevSceneColor, PrevSceneDepth
        test::MemorySink sink;
        executePlan(plan, src, sink);
        const Texture& color = sink.layers.at("prev_color_reduction.color");
        const Texture& alpha = sink.layers.at("prev_color_reduction.alpha");
        REQUIRE(color.mipCount() == 5);
        CHECK(color.mip(0).width() == 32);
        // Texels whose footprint lies in the centre 60 % of the screen have no vignette; there the
        // weight is 1 up to the half-precision HZB depth used from mip 2 on (weight error ~1e-6).
        for (int m = 0; m < 5; ++m) {
            const int span = 2 << m;
            for (int y = 0; y < color.mip(m).height(); ++y)
                for (int x = 0; x < color.mip(m).width(); ++x) {
                    const double sx0 = (x * span) / double(w) * 2 - 1,
                                 sx1 = ((x + 1) * span) / double(w) * 2 - 1;
                    const double sy0 = (y * span) / double(h) * 2 - 1,
                                 sy1 = ((y + 1) * span) / double(h) * 2 - 1;
                    if (std::max({std::fabs(sx0), std::fabs(sx1), std::fabs(sy0), std::fabs(sy1)}) >
                        0.8)
                        continue;
                    CHECK(alpha.mip(m).plane(0).at(x, y) == doctest::Approx(1.0).epsilon(1e-4));
                    for (int c = 0; c < 3; ++c)
                        CHECK(color.mip(m).plane(c).at(x, y) ==
                              doctest::Approx(c + 1.0).epsilon(1e-4));
                }
        }
        // At the screen border the vignette v(s) = 1 − saturate(5|s| − 4)² fades colour and weight
        // (algorithms §3.2 step 7): texel (0, 16) averages pixels 0 and 1 of a 64-pixel row.
        auto v = [](double s) {
            const double c = std::clamp(5 * std::fabs(s) - 4, 0.0, 1.0);
            return 1 - c * c;
        };
        const double expected = 0.5 * (v(0.5 / 64 * 2 - 1) + v(1.5 / 64 * 2 - 1));
        CHECK(alpha.mip(0).plane(0).at(0, 16) == doctest::Approx(expected).epsilon(1e-5));
        CHECK(color.mip(0).plane(2).at(0, 16) == doctest::Approx(3 * expected).epsilon(1e-5));
    }

    TEST_CASE("reduced previous colour: leak-free weighting drops colour from another surface") {
        // Last frame saw a surface twice as far: its colour must not leak into this frame.
        auto src = flatFrame(64, 64, 200.0f, {5.0f, 5.0f, 5.0f}, 400.0f);
        const Plan plan = test::planFor(
            {test::node("hzb"),
             test::node("prev_color_reduction", {}, {{"furthestHzb", "hzb.furthest"}})},
            {"prev_color_reduction.color"});
        test::MemorySink sink;
        executePlan(plan, src, sink);
        CHECK(sink.layers.at("prev_color_reduction.color").mip(0).plane(0).at(16, 16) == 0.0f);

        // r.SSGI.LeakFreeReprojection=0 reads the TAA history instead and keeps the colour.
        const Plan history = test::planFor(
            {test::node("hzb"),
             test::node("prev_color_reduction", {}, {{"furthestHzb", "hzb.furthest"}})},
            {"prev_color_reduction.color"}, {{"r.SSGI.LeakFreeReprojection", 0}});
        CHECK(history.steps[1].inputs.count("history") == 1);
        CHECK(history.steps[1].inputs.count("prevDepth") == 0);
        test::MemorySink sink2;
        executePlan(history, src, sink2);
        CHECK(sink2.layers.at("prev_color_reduction.color").mip(0).plane(0).at(16, 16) ==
              doctest::Approx(5.0));
    }

    TEST_CASE(
        "display: scene-linear 0.18 becomes sRGB 0.4614; data buffers are not colour-converted") {
        test::MemorySource src;
        src.info.extent = {4, 4};
        src.buffers["SceneColor"] = Image(4, 4, {"R", "G", "B"}, 0.18f);
        Image n(4, 4, {"X", "Y", "Z"}, 0.0f);
        n.plane(1) = Plane(4, 4, 0.5f);
        src.buffers["WorldNormal"] = n;
        const Plan plan =
            test::planFor({test::node("display"),
                           {"normals", "display", {}, {{"color", "capture:WorldNormal"}}, ""}},
                          {"display.image", "normals.image"});
        test::MemorySink sink;
        executePlan(plan, src, sink);
        // IEC 61966-2-1: 1.055·0.18^(1/2.4) − 0.055 = 0.46135.
        CHECK(sink.layers.at("display.image").image().plane(1).at(2, 2) ==
              doctest::Approx(0.46135).epsilon(1e-4));
        CHECK(sink.layers.at("normals.image").image().plane(1).at(2, 2) == 0.5f);
    }
}
