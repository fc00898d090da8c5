// The screen-space oracle against analytic answers: the on-screen form factor of a glowing wall,
// a mirror floor reflecting it, skipped pixels, and the same bits on any thread count.
#include "framework/Executor.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

using namespace fp;

namespace {

std::map<std::string, Texture> runOracle(test::MemorySource& src, nlohmann::json params,
                                         const std::vector<std::string>& ports) {
    std::vector<std::string> outputs;
    for (const auto& p : ports) outputs.push_back("screen_space_oracle." + p);
    test::MemorySink sink;
    executePlan(test::planFor({test::node("screen_space_oracle", params)}, outputs), src, sink, {});
    return sink.layers;
}

const Plane& layer(const std::map<std::string, Texture>& out, const std::string& port, int c = 0) {
    return out.at("screen_space_oracle." + port).image().plane(c);
}

}  // namespace

TEST_SUITE("screen_space_oracle") {

TEST_CASE("a floor beside a glowing wall gathers the on-screen form factor, without Unreal's losses") {
    const int size = 64, rays = 256;
    const Scene s = test::floorAndWall();
    const FrameCamera cam = test::wallCamera(size);
    auto src = test::captureToMemory(s, cam);
    const auto out = runOracle(src, {{"rays", rays}}, {"diffuse", "hitFraction", "ao"});
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    double sqErr = 0, sqNoise = 0, sumErr = 0;
    int n = 0;
    for (int y = 0; y < size; y += 2)
        for (int x = 0; x < size; x += 2) {
            const Vec3d p = cam.current.worldFromPixel(x, y, depth.at(x, y));
            if (std::abs(p.y) > 1e-3 || p.z > 28.0) continue;  // floor pixels only
            const double F = test::onScreenWallFormFactor(p, cam.current, [](double, double) { return 1.0; });
            const double h = layer(out, "hitFraction").at(x, y);
            // Every hit reads kGlow: the mean radiance is kGlow × the hit fraction, exactly up
            // to float sums of 256 equal terms (no Karis weight, no vignette, no mips).
            CHECK(layer(out, "diffuse").at(x, y) == doctest::Approx(test::kGlow * h).epsilon(1e-5));
            CHECK(layer(out, "ao").at(x, y) == doctest::Approx(1.0 - h).epsilon(1e-6));
            sqErr += (h - F) * (h - F);
            sumErr += h - F;
            sqNoise += F * (1 - F) / rays;  // variance of the hit fraction of independent rays
            ++n;
        }
    REQUIRE(n > 100);
    const double rmsErr = std::sqrt(sqErr / n), rmsNoise = std::sqrt(sqNoise / n);
    MESSAGE("hit fraction RMS error " << rmsErr << ", ray noise " << rmsNoise << ", bias " << sumErr / n);
    // Independent random rays: E[error²] = noise² + bias², and over 100+ pixels the measured RMS
    // lies within 15 % of its expectation; a systematic loss (a missed wall strip, a step schedule
    // that skips hits, SSGI's 0.37-of-0.72 hit fraction) would show as a bias far beyond noise/√n.
    CHECK(rmsErr < 1.15 * rmsNoise);
    CHECK(std::abs(sumErr / n) < 4.0 * rmsNoise / std::sqrt(double(n)));
}

TEST_CASE("a mirror floor reflects the glowing wall where the mirrored ray stays on screen") {
    const int size = 64;
    Scene s = test::floorAndWall();
    Material mirror = test::lambert(0.0f, test::kGlow);
    mirror.baseColor = {1, 1, 1};
    mirror.metallic = 1.0f;  // F = 1
    mirror.roughness = 0.0f;
    s.materials.push_back(mirror);
    s.meshes[0].material = 1;
    const FrameCamera cam = test::wallCamera(size);
    auto src = test::captureToMemory(s, cam);
    const auto out = runOracle(src, {{"rays", 16}}, {"specular"});
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    const CameraView& cv = cam.current;
    int onScreen = 0, offScreen = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const Vec3d p = cv.worldFromPixel(x, y, depth.at(x, y));
            if (std::abs(p.y) > 1e-3 || p.z > 28.0) continue;
            Vec3d d = p - cv.position;
            d.y = -d.y;  // the mirrored view ray
            const auto q = cv.project(p + d * ((30.0 - p.z) / d.z));
            const double margin = std::min({q.px, q.py, size - q.px, size - q.py});
            // Within 4 pixels of the screen's edge the march's last samples decide (its end is
            // clipped to the border), which this test does not model.
            if (std::abs(margin) < 4.0) continue;
            // GGX at roughness 0 is clamped to α = 4·10⁻⁴ (BRDF.h): F·G2/G1 is 1 to 10⁻³.
            const double expected = margin > 0 ? test::kGlow : 0.0;
            (margin > 0 ? onScreen : offScreen)++;
            for (int c = 0; c < 3; ++c)
                CHECK(layer(out, "specular", c).at(x, y) == doctest::Approx(expected).epsilon(1e-3));
        }
    CHECK(onScreen > 100);
    CHECK(offScreen > 40);
}

TEST_CASE("sky and unlit pixels are skipped: no rays, diffuse 0, AO 1") {
    Scene s = test::floorScene();
    Material unlit = test::lambert(0.7f, 0.3f);
    unlit.shadingModel = 0;
    s.materials.push_back(unlit);
    s.meshes.push_back(test::quad({0, 5, 20}, {1, 0, 0}, {0, 1, 0}, 5.0, 1, 2));
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 10, -30}, {0, 5, 20}, {0, 1, 0}, 60.0, 32, 24, 1.0);
    auto src = test::captureToMemory(s, cam);
    const auto out = runOracle(src, {{"rays", 8}}, {"diffuse", "ao", "aoWithinRadius"});
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    const Plane& model = src.buffers.at("ShadingModel").plane(0);
    int skipped = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) {
            if (!std::isinf(depth.at(x, y)) && model.at(x, y) != 0.0f) continue;
            ++skipped;
            CHECK(layer(out, "ao").at(x, y) == 1.0f);
            CHECK(layer(out, "aoWithinRadius").at(x, y) == 1.0f);
            CHECK(layer(out, "diffuse").at(x, y) == 0.0f);
        }
    CHECK(skipped > 100);
}

TEST_CASE("the oracle gives the same bits on 1 or 2 threads") {
    const Scene s = test::floorAndWall();
    const FrameCamera cam = test::wallCamera(80);  // several tiles
    auto src = test::captureToMemory(s, cam);
    const std::vector<std::string> ports = {"diffuse", "aoWithinRadius"};
    const auto a = runOracle(src, {{"rays", 4}}, ports);
    std::map<std::string, Texture> b;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        b = runOracle(src, {{"rays", 4}}, ports);
    }
    for (const auto& p : ports) CHECK(test::sameBits(layer(a, p), layer(b, p)));
}

}  // TEST_SUITE
