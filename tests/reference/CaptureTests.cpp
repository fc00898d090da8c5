#include "reference/GBufferRenderer.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

using namespace fp;

namespace {
FrameCamera floorCamera(const Vec3d& offset, int w = 48, int h = 32) {
    FrameCamera cam;
    cam.current = CameraView::lookAt(offset + Vec3d{3, 40, -60}, offset + Vec3d{0, 0, 10}, {0, 1, 0},
                                     55.0, w, h, 10.0);
    cam.previous = cam.current;
    return cam;
}
}  // namespace

TEST_SUITE("capture") {

TEST_CASE("the capture of a plane has the analytic depth and normal at every pixel") {
    const Scene scene = test::floorScene();
    const FrameCamera cam = floorCamera({});
    const auto buffers = GBufferRenderer(scene, cam, {}).render().buffers;
    const CameraView& c = cam.current;
    int hits = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const Vec3d d = c.rayDirection(x, y);
            const double t = -c.position.y / d.y;  // ray meets y = 0
            const Vec3d p = c.position + d * t;
            const bool inside = d.y < 0 && std::fabs(p.x) < 100 && std::fabs(p.z) < 100;
            const float depth = buffers.at("SceneDepth").plane(0).at(x, y);
            if (!inside) {
                CHECK(std::isinf(depth));
                continue;
            }
            ++hits;
            // Float ray-triangle intersection: a few ulps of the hit distance.
            CHECK(depth == doctest::Approx(t * dot(d, c.forward)).epsilon(2e-6));
            CHECK(buffers.at("WorldNormal").plane(0).at(x, y) == 0.0f);
            CHECK(buffers.at("WorldNormal").plane(1).at(x, y) == 1.0f);
            CHECK(buffers.at("WorldNormal").plane(2).at(x, y) == 0.0f);
            CHECK(buffers.at("ShadingModel").plane(0).at(x, y) == 1.0f);
            CHECK(buffers.at("BaseColor").plane(0).at(x, y) == 0.5f);
        }
    CHECK(hits > c.width * c.height / 3);
}

TEST_CASE("a point light's direct lighting on a Lambert plane is albedo/π · I·cosθ/r²") {
    Scene scene = test::floorScene();
    Light l;
    l.type = LightType::Point;
    l.position = {5, 30, 12};
    l.intensity = 2000.0f;
    scene.lights.push_back(l);
    const FrameCamera cam = floorCamera({});
    const auto buffers = GBufferRenderer(scene, cam, {}).render().buffers;
    const CameraView& c = cam.current;
    int checked = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const float depth = buffers.at("SceneDepth").plane(0).at(x, y);
            if (std::isinf(depth)) continue;
            const Vec3d p = c.worldFromPixel(x, y, depth);
            const Vec3d toLight = l.position - p;
            const double r2 = dot(toLight, toLight);
            const double cosTheta = toLight.y / std::sqrt(r2);
            const double expected = 0.5 / kPi * l.intensity * cosTheta / r2;
            CHECK(buffers.at("SceneColor").plane(0).at(x, y) == doctest::Approx(expected).epsilon(1e-4));
            ++checked;
        }
    CHECK(checked > 0);
}

TEST_CASE("hard case: a camera 10^7 units from the origin captures what one at the origin does") {
    Scene near = test::floorScene(), far = test::floorScene({1e7, 0, -1e7});
    Light l;
    l.position = {5, 30, 12};
    l.intensity = 2000.0f;
    near.lights.push_back(l);
    l.position += Vec3d{1e7, 0, -1e7};
    far.lights.push_back(l);
    const auto a = GBufferRenderer(near, floorCamera({}), {}).render().buffers;
    const auto b = GBufferRenderer(far, floorCamera({1e7, 0, -1e7}), {}).render().buffers;
    // Geometry is rebased on the camera in double before Embree sees it: identical inputs, so
    // identical bits, except where the float vertex offsets round differently (none here).
    for (const char* name : {"SceneDepth", "SceneColor", "WorldNormal"})
        for (int c = 0; c < a.at(name).channelCount(); ++c)
            CHECK(test::sameBits(a.at(name).plane(c), b.at(name).plane(c)));
}

TEST_CASE("velocity points to where the surface was under the previous camera") {
    const Scene scene = test::floorScene();
    FrameCamera cam = floorCamera({});
    cam.previous->position += Vec3d{2.0, 0, 0};
    const auto buffers = GBufferRenderer(scene, cam, {}).render().buffers;
    const int x = 20, y = 20;
    const float depth = buffers.at("SceneDepth").plane(0).at(x, y);
    const auto proj = cam.previous->project(cam.current.worldFromPixel(x, y, depth));
    CHECK(buffers.at("Velocity").plane(0).at(x, y) == doctest::Approx(proj.px - (x + 0.5)).epsilon(1e-4));
    CHECK(buffers.at("Velocity").plane(1).at(x, y) == doctest::Approx(proj.py - (y + 0.5)).epsilon(1e-4));
    CHECK(buffers.at("Velocity").plane(0).at(x, y) != 0.0f);
}

TEST_CASE("the capture is bit-identical with 1 and 2 threads") {
    Scene scene = test::floorScene();
    scene.meshes.push_back(test::quad({0, 10, 0}, {1, 0, 0}, {0, 0, 1}, 8.0, 0, 2));
    Light l;
    l.type = LightType::Rect;
    l.position = {0, 40, 0};
    l.halfU = {5, 0, 0};
    l.halfV = {0, 0, 5};
    l.intensity = 20.0f;
    scene.lights.push_back(l);
    const FrameCamera cam = floorCamera({}, 150, 70);
    auto render = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return GBufferRenderer(scene, cam, {}).render().buffers;
    };
    const auto one = render(1), two = render(2);
    for (const auto& [layer, img] : one) {
        const std::string& name = layer;  // (clang 14 cannot capture a structured binding)
        for (int c = 0; c < img.channelCount(); ++c)
            CHECK_MESSAGE(test::sameBits(img.plane(c), two.at(name).plane(c)), name);
    }
}

}
