#include "foundation/Error.h"
#include "framework/Executor.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace fp;

TEST_SUITE("camera_velocity") {
    TEST_CASE("camera motion vectors from depth equal the capture's velocity of a static scene") {
        // The capture projects each exact hit point through last frame's camera; camera_velocity
        // rebuilds the point from the float32 depth. Both are the same projection, so they agree to
        // the depth's rounding: 2⁻²⁴ relative of a ≤ 100-unit depth moves a pixel by far less than
        // 10⁻³ of a pixel at this field of view.
        const Scene scene = test::floorScene();
        FrameCamera cam;
        cam.current = CameraView::lookAt({0, 40, -10}, {0, 0, 10}, {0, 1, 0}, 60.0, 48, 32, 1.0);
        cam.previous = CameraView::lookAt({-3, 42, -12}, {1, 0, 9}, {0, 1, 0}, 60.0, 48, 32, 1.0);
        auto src = test::captureToMemory(scene, cam);
        test::MemorySink sink;
        executePlan(test::planFor({test::node("camera_velocity")}, {"camera_velocity.velocity"}),
                    src, sink);
        const Image& v = sink.layers.at("camera_velocity.velocity").image();
        const Image& truth = src.buffers.at("Velocity");
        double largest = 0.0, moved = 0.0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 48; ++x)
                for (int c = 0; c < 2; ++c) {
                    largest = std::max(
                        largest, double(std::fabs(v.plane(c).at(x, y) - truth.plane(c).at(x, y))));
                    moved = std::max(moved, double(std::fabs(truth.plane(c).at(x, y))));
                }
        CHECK(moved > 1.0);  // the camera did move: the check is not of zeros
        CHECK(largest < 1e-3);
    }

    TEST_CASE("a still camera gives zero motion, and a missing previous camera is an error") {
        const Scene scene = test::floorScene();
        FrameCamera cam;
        cam.current = CameraView::lookAt({0, 40, -10}, {0, 0, 10}, {0, 1, 0}, 60.0, 16, 16, 1.0);
        cam.previous = cam.current;
        auto src = test::captureToMemory(scene, cam);
        const Plan plan =
            test::planFor({test::node("camera_velocity")}, {"camera_velocity.velocity"});
        test::MemorySink sink;
        executePlan(plan, src, sink);
        const Image& v = sink.layers.at("camera_velocity.velocity").image();
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                CHECK(std::fabs(v.plane(0).at(x, y)) < 1e-4);
                CHECK(std::fabs(v.plane(1).at(x, y)) < 1e-4);
            }
        src.info.camera.previous.reset();
        test::MemorySink sink2;
        CHECK_THROWS_WITH_AS(executePlan(plan, src, sink2),
                             doctest::Contains("last frame's camera"), Error);
    }
}
