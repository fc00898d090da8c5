#include "foundation/Camera.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace fp;

TEST_SUITE("camera") {

TEST_CASE("device Z is near/depth for Unreal's infinite reversed-Z projection") {
    CameraView c = CameraView::lookAt({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 60.0, 64, 64, 10.0);
    // algorithms §1.2: DeviceZ = NearZ / SceneDepth; near → 1, sky → 0.
    CHECK(c.deviceZFromDepth(10.0) == doctest::Approx(1.0));
    CHECK(c.deviceZFromDepth(250.0) == doctest::Approx(10.0 / 250.0));
    CHECK(c.deviceZFromDepth(INFINITY) == 0.0);
    CHECK(std::isinf(c.depthFromDeviceZ(0.0)));
    for (double d : {10.0, 12.5, 1e3, 1e6, 3.3e8})
        CHECK(c.depthFromDeviceZ(c.deviceZFromDepth(d)) == doctest::Approx(d).epsilon(1e-12));
}

TEST_CASE("a finite far plane maps far to device Z 0 and back") {
    CameraView c = CameraView::lookAt({0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 60.0, 64, 64, 10.0);
    c.farPlane = 1000.0;
    CHECK(c.deviceZFromDepth(10.0) == doctest::Approx(1.0));
    CHECK(c.deviceZFromDepth(1000.0) == doctest::Approx(0.0).epsilon(1e-12));
    CHECK(c.depthFromDeviceZ(c.deviceZFromDepth(333.0)) == doctest::Approx(333.0));
}

TEST_CASE("matrices round-trip through fromMatrices") {
    CameraView c = CameraView::lookAt({3, 4, 5}, {-2, 1, 9}, {0, 1, 0}, 45.0, 80, 40, 7.0);
    c.cx = 0.1;
    c.cy = -0.05;
    CameraView r = CameraView::fromMatrices(c.viewMatrix(), c.projectionMatrix(), 80, 40);
    CHECK(length(r.position - c.position) < 1e-12);
    CHECK(length(r.forward - c.forward) < 1e-12);
    CHECK(r.fx == doctest::Approx(c.fx));
    CHECK(r.cy == doctest::Approx(c.cy));
    CHECK(r.nearPlane == doctest::Approx(7.0));
}

TEST_CASE("projecting a reconstructed position returns the pixel and depth") {
    CameraView c = CameraView::lookAt({1, 2, 3}, {4, 0, 20}, {0, 1, 0}, 50.0, 100, 60, 1.0);
    const Vec3d w = c.worldFromPixel(37, 21, 42.0);
    const auto p = c.project(w);
    CHECK(p.px == doctest::Approx(37.5));
    CHECK(p.py == doctest::Approx(21.5));
    CHECK(p.depth == doctest::Approx(42.0));
}

TEST_CASE("hard case: reconstruction 10^7 units from the origin keeps millimetre precision") {
    // Unreal units are centimetres: 1 mm = 0.1 units. A float world position at 1e7 has a step
    // of 1 unit, so only camera-relative maths can hold 0.1.
    const Vec3d eye{1e7, 5e6, -1e7};
    CameraView c = CameraView::lookAt(eye, eye + Vec3d{0.3, -0.2, 1.0}, {0, 1, 0}, 60.0, 1920,
                                      1080, 10.0);
    CameraView origin = c;
    origin.position = {0, 0, 0};
    for (double depth : {15.0, 333.3, 2500.0}) {
        const Vec3d far = c.translatedFromPixel(811.0, 402.0, depth);
        const Vec3d near = origin.translatedFromPixel(811.0, 402.0, depth);
        CHECK(length(far - near) < 1e-9);  // the offset does not depend on where the eye is
        // The absolute position, subtracted back in double, is within 0.1 units (1 mm).
        const Vec3d world = c.worldFromPixel(811.0, 402.0, depth);
        CHECK(length((world - eye) - near) < 0.1 * 1e-3);
        const auto p = c.project(world);
        CHECK(p.depth == doctest::Approx(depth).epsilon(1e-9));
    }
}

}
