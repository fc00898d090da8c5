// error_measure inside a chain: the figures it reports for the run (and bench) are those of
// measureError on the same pixels, the sky is left out, and its outputs are the per-pixel |error|
// and the heat map.
#include "metrics/ErrorMetrics.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>

using namespace fp;

TEST_SUITE("error_measure") {
    TEST_CASE("it reports measureError's figures over the pixels that are not sky") {
        // 8×4: source 1 everywhere; reference 0.5 on the left half, 1 on the right; the top row
        // is sky (+inf depth) with a wild reference value that must not count.
        const int w = 8, h = 4;
        test::MemorySource src;
        src.info.extent = {w, h};
        Image a(w, h, {"R", "G", "B"}, 1.0f), b(w, h, {"R", "G", "B"}, 1.0f);
        Image depth(w, h, {"Z"}, 100.0f);
        for (int x = 0; x < w; ++x) depth.plane(0).at(x, 0) = std::numeric_limits<float>::infinity();
        for (int c = 0; c < 3; ++c)
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    b.plane(c).at(x, y) = y == 0 ? 1000.0f : x < w / 2 ? 0.5f : 1.0f;
        src.buffers["SceneColor"] = a;
        src.buffers["BaseColor"] = b;
        src.buffers["SceneDepth"] = depth;
        const Plan plan = test::planFor(
            {test::node("error_measure", {},
                        {{"source", "capture:SceneColor"}, {"reference", "capture:BaseColor"}})},
            {"error_measure.absError", "error_measure.heat"});
        test::MemorySink sink;
        const FrameReport report = executePlan(plan, src, sink);
        REQUIRE(report.passes.size() == 1);
        const auto& m = report.passes[0].metrics;

        // Half the 24 measured pixels are off by 0.5 in every channel: RMSE √(0.25/2), bias and
        // MAE 0.25, max 0.5. The same pixels through measureError give the same figures.
        CHECK(m.at("rmse") == doctest::Approx(std::sqrt(0.125)));
        CHECK(m.at("bias") == doctest::Approx(0.25));
        CHECK(m.at("mae") == doctest::Approx(0.25));
        CHECK(m.at("maxError") == doctest::Approx(0.5));
        CHECK(report.passes[0].work.at("pixels") == 24);
        CHECK(report.passes[0].work.at("skippedPixels") == 8);
        const Image mask = notSkyMask(depth, std::numeric_limits<float>::infinity());
        ErrorInputs in{&a, &b, nullptr, &mask, 0.1};
        CHECK(m.at("rmse") == measureError(in).rmse);

        const Image& abs = sink.layers.at("error_measure.absError").image();
        CHECK(abs.plane(0).at(1, 2) == 0.5f);
        CHECK(abs.plane(0).at(6, 2) == 0.0f);
        CHECK(sink.layers.at("error_measure.heat").image().channelCount() == 3);
    }

    TEST_CASE("an exclude input leaves out the pixels above excludeAbove, with the sky") {
        // The scene above: the left half off by 0.5, the top row sky. An exclude layer of 1 on
        // the left half's columns 0–1 and 0.3 on columns 2–3 leaves out 2 or 4 columns.
        const int w = 8, h = 4;
        test::MemorySource src;
        src.info.extent = {w, h};
        Image a(w, h, {"R", "G", "B"}, 1.0f), b(w, h, {"R", "G", "B"}, 1.0f);
        Image depth(w, h, {"Z"}, 100.0f), exclude(w, h, {"Y"}, 0.0f);
        for (int x = 0; x < w; ++x) depth.plane(0).at(x, 0) = std::numeric_limits<float>::infinity();
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w / 2; ++x) {
                for (int c = 0; c < 3; ++c) b.plane(c).at(x, y) = 0.5f;
                exclude.plane(0).at(x, y) = x < 2 ? 1.0f : 0.3f;
            }
        src.buffers["SceneColor"] = a;
        src.buffers["BaseColor"] = b;
        src.buffers["SceneDepth"] = depth;
        src.buffers["Truth.ReflectedEmitter"] = exclude;
        for (const auto& [above, columnsOut] : {std::pair{0.0, 4}, std::pair{0.5, 2}}) {
            CAPTURE(above);
            const Plan plan = test::planFor(
                {test::node("error_measure", {{"excludeAbove", above}},
                            {{"source", "capture:SceneColor"},
                             {"reference", "capture:BaseColor"},
                             {"exclude", "capture:Truth.ReflectedEmitter"}})},
                {"error_measure.absError"});
            test::MemorySink sink;
            const FrameReport report = executePlan(plan, src, sink);
            REQUIRE(report.passes.size() == 1);
            const auto& m = report.passes[0].metrics;
            // 3 rows under the sky; of the 4 wrong columns, 4 − columnsOut are measured.
            const int measured = 3 * (w - columnsOut), wrong = 3 * (w / 2 - columnsOut);
            CHECK(report.passes[0].work.at("pixels") == measured);
            CHECK(report.passes[0].work.at("skippedPixels") == w * h - measured);
            CHECK(m.at("rmse") == doctest::Approx(std::sqrt(0.25 * wrong / measured)));
        }
    }
}
