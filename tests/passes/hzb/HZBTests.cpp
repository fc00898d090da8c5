// hzb: Unreal's sizing, texels against a brute-force min/max of device Z, half rounding.
#include "foundation/HalfFloat.h"
#include "passes/hzb/HZBPass.h"
#include "framework/Executor.h"
#include "framework/Planner.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace fp;

TEST_SUITE("hzb") {
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
}
