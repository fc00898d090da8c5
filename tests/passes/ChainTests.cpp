// The built-in passes run through the real planner and executor on in-memory captures.
#include "passes/core/Executor.h"
#include "passes/core/HalfFloat.h"
#include "passes/core/Planner.h"
#include "passes/hzb/HZBPass.h"
#include "passes/prev_color_reduction/PrevColorReductionPass.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

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

TEST_SUITE("passes") {
    TEST_CASE("HZB has Unreal's size and mip count") {
        const auto e = HZBPass::mipExtents({1920, 1080});
        CHECK(e.size() == 10);
        CHECK(e[0] == Extent{1024, 1024});
        CHECK(e[9] == Extent{2, 2});
        CHECK(HZBPass::mipExtents({50, 37})[0] == Extent{32, 32});
    }

    TEST_CASE("HZB texels equal a brute-force min/max of device Z over their footprint") {
        const int w = 50, h = 37;
        test::MemorySource src;
        src.info.extent = {w, h};
        src.info.camera.current =
            CameraView::lookAt({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 60.0, w, h, 10.0);
        src.info.hasCamera = true;
        Image depth(w, h, {"Z"});
        std::mt19937 gen(7);
        std::uniform_real_distribution<float> dist(10.0f, 5000.0f);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                depth.plane(0).at(x, y) = (x * y) % 11 == 3 ? INFINITY : dist(gen);  // some sky
        src.buffers["SceneDepth"] = depth;
        for (bool half : {false, true}) {
            const Plan plan = test::planFor({test::node("hzb", {{"halfPrecision", half}})},
                                            {"hzb.furthest", "hzb.closest"});
            test::MemorySink sink;
            executePlan(plan, src, sink);
            const Texture& far = sink.layers.at("hzb.furthest");
            const Texture& near = sink.layers.at("hzb.closest");
            const auto& cam = src.info.camera.current;
            for (int m = 0; m < far.mipCount(); ++m) {
                const int span = 2 << m;  // full-res pixels per texel side
                const Image& fm = far.mip(m);
                for (int y = 0; y < fm.height(); ++y)
                    for (int x = 0; x < fm.width(); ++x) {
                        float lo = 1e30f, hi = -1e30f;
                        for (int j = 0; j < span; ++j)
                            for (int i = 0; i < span; ++i) {
                                // Mip 0 clamps reads to the view; higher mips clamp to mip 0's
                                // size.
                                int px = std::min(x * span + i,
                                                  2 * HZBPass::mipExtents({w, h})[0].width - 1);
                                int py = std::min(y * span + j,
                                                  2 * HZBPass::mipExtents({w, h})[0].height - 1);
                                const float z = float(cam.deviceZFromDepth(depth.plane(0).clampedAt(
                                    std::min(px, w - 1), std::min(py, h - 1))));
                                lo = std::min(lo, half ? roundToHalf(z) : z);
                                hi = std::max(hi, half ? roundToHalf(z) : z);
                            }
                        CHECK(fm.plane(0).at(x, y) == lo);
                        CHECK(near.mip(m).plane(0).at(x, y) == hi);
                    }
            }
        }
    }

    TEST_CASE("roundToHalf matches IEEE half rounding") {
        CHECK(roundToHalf(1.0f) == 1.0f);
        CHECK(roundToHalf(1.0f + 1.0f / 4096) == 1.0f);  // below half an ulp (2^-11)
        CHECK(roundToHalf(1.0f + 3.0f / 4096) == 1.0f + 1.0f / 1024);
        CHECK(roundToHalf(65504.0f) == 65504.0f);
        CHECK(std::isinf(roundToHalf(70000.0f)));
        CHECK(roundToHalf(3e-8f) ==
              std::ldexp(1.0f, -24) * 1.0f * std::nearbyint(3e-8f / std::ldexp(1.0f, -24)));
    }

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

    TEST_CASE("a whole chain is bit-identical with 1 and 2 threads") {
        Scene scene = test::floorScene();
        scene.meshes.push_back(test::quad({0, 10, 0}, {1, 0, 0}, {0, 0, 1}, 8.0, 0, 2));
        Light l;
        l.position = {0, 40, 0};
        l.intensity = 3000.0f;
        scene.lights.push_back(l);
        FrameCamera cam;
        cam.current = CameraView::lookAt({3, 40, -60}, {0, 0, 10}, {0, 1, 0}, 55.0, 130, 90, 10.0);
        cam.previous = cam.current;
        cam.previous->position += Vec3d{1.5, 0.5, 0};
        auto run = [&](int threads) {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
            auto src = test::captureToMemory(scene, cam);
            const Plan plan = test::planFor(
                {test::node("hzb"),
                 test::node("prev_color_reduction", {}, {{"furthestHzb", "hzb.furthest"}}),
                 test::node("display")},
                {"hzb.furthest", "prev_color_reduction.color", "display.image"});
            test::MemorySink sink;
            executePlan(plan, src, sink);
            return sink.layers;
        };
        const auto one = run(1), two = run(2);
        for (const auto& [name, tex] : one)
            for (int m = 0; m < tex.mipCount(); ++m)
                for (int c = 0; c < tex.mip(m).channelCount(); ++c)
                    CHECK_MESSAGE(test::sameBits(tex.mip(m).plane(c), two.at(name).mip(m).plane(c)),
                                  name << " mip " << m);
    }
}
