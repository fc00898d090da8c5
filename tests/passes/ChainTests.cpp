// A chain of built-in passes through the real planner and executor: the same bits on any
// thread count. (Each pass has its tests in tests/passes/<id>/.)
#include "framework/Executor.h"
#include "framework/Planner.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

using namespace fp;

TEST_SUITE("passes") {
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
        for (const auto& [layer, tex] : one) {
            const std::string& name = layer;  // (clang 14 cannot capture a structured binding)
            for (int m = 0; m < tex.mipCount(); ++m)
                for (int c = 0; c < tex.mip(m).channelCount(); ++c)
                    CHECK_MESSAGE(test::sameBits(tex.mip(m).plane(c), two.at(name).mip(m).plane(c)),
                                  name << " mip " << m);
        }
    }
}
