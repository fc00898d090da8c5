// rt_global_illumination against analytic answers and the path-traced truth: an open floor
// gathers nothing (no emission at hits, no sky on the first ray), a wall beside a sunlit floor
// gathers half the floor's radiance in one bounce, and many bounces converge to
// Truth.DiffuseIndirectFull in a closed room.
#include "reference/TruthRenderer.h"
#include "tests/support/LaneTargets.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace fp {

namespace {

std::map<std::string, Texture> runGi(test::MemorySource& src, nlohmann::json params) {
    return test::runChain(src, {test::node("rt_global_illumination", std::move(params))},
                          {"rt_global_illumination.diffuse", "rt_global_illumination.ao",
                           "rt_global_illumination.hitDistance"});
}

FrameCamera lookAt(const Vec3d& eye, const Vec3d& target, const Vec3d& up, int size, double fov) {
    FrameCamera cam;
    cam.current = CameraView::lookAt(eye, target, up, fov, size, size, 0.1);
    cam.previous = cam.current;
    return cam;
}

}  // namespace

TEST_CASE("rt_global_illumination: an open floor under a sky and a sun gathers nothing") {
    // Every first ray leaves the scene: Unreal adds the sky only to bounce rays, and a hit's
    // emission never (the floor glows here).
    Scene scene = test::floorScene();
    scene.sceneUnitsPerMeter = 100.0;
    scene.materials[0].emission = {1, 1, 1};
    scene.lights.push_back(test::sun({0, -1, 0}));
    scene.environment.sky.enabled = true;
    auto src = test::captureToMemory(scene, test::topCamera({}, 16));
    const auto out = runGi(src, {{"samplesPerPixel", 4}, {"maxBounces", 3}, {"evalSkyLight", true}});
    const Image& gi = out.at("rt_global_illumination.diffuse").image();
    for (int c = 0; c < 3; ++c)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) CHECK(gi.plane(c).at(x, y) == 0.0f);
    const Plane& ao = out.at("rt_global_illumination.ao").image().plane(0);
    const Plane& hit = out.at("rt_global_illumination.hitDistance").image().plane(0);
    CHECK(ao.at(8, 8) == 1.0f);
    CHECK(hit.at(8, 8) == -1.0f);
}

TEST_CASE("rt_global_illumination: a wall beside a sunlit floor gathers half the floor's radiance") {
    // A sun straight down lights the floor y = 0 (albedo 0.5) with irradiance 1 and grazes the wall
    // x = 0 (cos 0: unlit, and it casts no shadow). The floor's radiance is 0.5/π; a wall point
    // sees it over the lower half of its cosine-weighted hemisphere (the floor reaches 10⁴ units,
    // so what it misses is a cone of cos² < 10⁻⁵), so one bounce gathers 0.5·0.5/π.
    Scene scene;
    scene.sceneUnitsPerMeter = 100.0;
    scene.materials.push_back(test::lambert(0.5f));
    scene.meshes.push_back(test::quad({-10000, 0, 0}, {0, 0, 1}, {1, 0, 0}, 10000, 0, 1));  // +y
    scene.meshes.push_back(test::quad({0, 10000, 0}, {0, 0, 1}, {0, 1, 0}, 10000, 0, 2));   // −x
    scene.lights.push_back(test::sun({0, -1, 0}));
    // Looking at the wall from x = −20, its points 5 to 15 units above the floor.
    auto src = test::captureToMemory(scene, lookAt({-20, 10, 0}, {0, 10, 0}, {0, 1, 0}, 24, 20.0));
    const int spp = 16;
    // Through Embree and through framepass's BVH (the GPU's code).
    for (const char* traversal : {"embree", "bvh"}) {
        INFO(traversal);
        const auto out =
            runGi(src, {{"samplesPerPixel", spp}, {"maxBounces", 1}, {"traversal", traversal}});
        const Image& gi = out.at("rt_global_illumination.diffuse").image();
        const Plane& instance = src.buffers.at("InstanceId").plane(0);
        const double floorRadiance = 0.5 / kPi, expected = 0.5 * floorRadiance;
        double sum = 0;
        int n = 0;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                if (instance.at(x, y) != 2.0f) continue;  // wall pixels
                sum += gi.plane(0).at(x, y);
                CHECK(gi.plane(1).at(x, y) == gi.plane(0).at(x, y));  // grey
                ++n;
            }
        REQUIRE(n > 400);
        // Each path gathers floorRadiance or 0 with probability ½: σ of the mean =
        // ½·floorRadiance/√N.
        const double sigma = 0.5 * floorRadiance / std::sqrt(double(n) * spp);
        CHECK(std::fabs(sum / n - expected) < 4.0 * sigma);
    }
}

TEST_CASE("rt_global_illumination: the BVH path, the GPU's code, follows Embree's paths") {
    // A smooth sphere on a floor under a sun and a soft point light, 4 paths of 2 bounces a
    // pixel: closest hits, interpolated normals, light samples and shadow rays all run. Both
    // paths draw the same random numbers, so they trace the same rays as long as every hit
    // decides alike; the two triangle tests (and barycentrics) round differently, so a hit's
    // position and normal may differ in their last bits and what the next rays gather with them.
    Scene scene = test::floorScene();
    scene.sceneUnitsPerMeter = 100.0;
    scene.meshes.push_back(test::sphere({0, 12, 0}, 10.0, 32, 0, 2));
    scene.lights.push_back(test::sun({0.3, -1, 0.2}));
    Light bulb;
    bulb.type = LightType::Point;
    bulb.position = {15, 30, 5};
    bulb.radius = 2.0f;
    bulb.intensity = 400.0f;
    scene.lights.push_back(bulb);
    auto src = test::captureToMemory(scene, test::topCamera({}, 64));
    auto trace = [&](const char* traversal, int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return runGi(src, {{"samplesPerPixel", 4}, {"maxBounces", 2}, {"traversal", traversal}});
    };
    const auto embree = trace("embree", 2), bvh = trace("bvh", 2), oneThread = trace("bvh", 1);
    for (const char* name : {"rt_global_illumination.diffuse", "rt_global_illumination.ao",
                             "rt_global_illumination.hitDistance"})
        for (int c = 0; c < bvh.at(name).image().channelCount(); ++c)
            CHECK(test::sameBits(bvh.at(name).image().plane(c), oneThread.at(name).image().plane(c)));
    const Image& ge = embree.at("rt_global_illumination.diffuse").image();
    const Image& gb = bvh.at("rt_global_illumination.diffuse").image();
    const Plane& ae = embree.at("rt_global_illumination.ao").image().plane(0);
    const Plane& ab = bvh.at("rt_global_illumination.ao").image().plane(0);
    int pixels = 0, lit = 0, differs = 0, aoDiffers = 0;
    double sumE = 0, sumB = 0;
    for (int y = 0; y < ge.height(); ++y)
        for (int x = 0; x < ge.width(); ++x) {
            ++pixels;
            aoDiffers += ae.at(x, y) != ab.at(x, y);  // a first ray hit within the radius or not
            for (int c = 0; c < 3; ++c) {
                const double e = ge.plane(c).at(x, y), b = gb.plane(c).at(x, y);
                sumE += e;
                sumB += b;
                lit += c == 0 && e > 0.0;
                // Rounding in the last bits of a hit carried through two bounces and a light
                // sample stays far below 10⁻⁴ relative; more is a ray that decided otherwise.
                if (std::fabs(e - b) > 1e-4 * std::max(std::fabs(e), 1e-6)) {
                    ++differs;
                    break;
                }
            }
        }
    MESSAGE("pixels " << pixels << ", lit " << lit << ": radiance differs beyond 1e-4 at " << differs
                      << ", ao at " << aoDiffers << "; mean " << sumE / pixels << " against "
                      << sumB / pixels);
    CHECK(lit > 400);  // the floor around the sphere and the sphere gather light
    // A pixel's 4 paths trace up to 8 closest-hit rays and 8 shadow rays; one that passes within
    // a few float steps of an edge may decide otherwise: at most one pixel in a hundred.
    CHECK(differs * 100 <= pixels);
    CHECK(aoDiffers * 1000 <= pixels);
    CHECK(sumB == doctest::Approx(sumE).epsilon(1e-3));
}

TEST_CASE("rt_global_illumination: many bounces converge to the path-traced full GI") {
    // A closed room (albedo 0.5, no emission) lit by a point light: with no sky and nothing
    // glowing, full GI is exactly what RTGI's paths gather; 10 bounces leave out 0.5¹⁰ of it.
    Scene scene;
    scene.sceneUnitsPerMeter = 100.0;
    scene.materials.push_back(test::lambert(0.5f));
    const Vec3d X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
    scene.meshes.push_back(test::quad({0, 0, 0}, Z, X, 50, 0, 1));     // floor, +y
    scene.meshes.push_back(test::quad({0, 100, 0}, X, Z, 50, 0, 2));   // ceiling, −y
    scene.meshes.push_back(test::quad({50, 50, 0}, Z, Y, 50, 0, 3));   // x = 50, −x
    scene.meshes.push_back(test::quad({-50, 50, 0}, Y, Z, 50, 0, 4));  // x = −50, +x
    scene.meshes.push_back(test::quad({0, 50, 50}, Y, X, 50, 0, 5));   // z = 50, −z
    scene.meshes.push_back(test::quad({0, 50, -50}, X, Y, 50, 0, 6));  // z = −50, +z
    Light bulb;
    bulb.name = "bulb";
    bulb.type = LightType::Point;
    bulb.position = {10, 70, 5};
    bulb.intensity = 1000.0f;
    scene.lights.push_back(bulb);
    const FrameCamera cam = lookAt({0, 50, -45}, {0, 30, 50}, {0, 1, 0}, 16, 80.0);
    auto src = test::captureToMemory(scene, cam);
    const auto out = runGi(src, {{"samplesPerPixel", 64}, {"maxBounces", 10}});
    const Image& gi = out.at("rt_global_illumination.diffuse").image();
    TruthSettings ts;
    ts.samplesPerPixel = 256;
    const TruthResult truth = TruthRenderer(scene, cam, ts).render();
    const Image& full = truth.layers.at("Truth.DiffuseIndirectFull");
    const Image& fullErr = truth.layers.at("Truth.DiffuseIndirectFull.StdErr");
    // The image means: the truth's noise from its standard errors, RTGI's bounded by the spread
    // of its pixel values (each pixel a mean of 64 paths).
    double a = 0, b = 0, truthVar = 0, spread = 0;
    const int n = 16 * 16;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            a += gi.plane(0).at(x, y);
            b += full.plane(0).at(x, y);
            truthVar += std::pow(fullErr.plane(0).at(x, y), 2.0);
        }
    const double meanGi = a / n;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) spread += std::pow(gi.plane(0).at(x, y) - meanGi, 2.0);
    // Pixel-to-pixel spread over-estimates RTGI's noise (it includes the image's own variation).
    const double sigma = std::sqrt(truthVar / (double(n) * n) + spread / (double(n) * (n - 1)) / n);
    CAPTURE(meanGi);
    CAPTURE(b / n);
    CHECK(b / n > 0.0);
    CHECK(std::fabs(meanGi - b / n) < 4.0 * sigma + 0.001 * b / n);
    CHECK(sigma < 0.05 * b / n);  // the check can tell a missing bounce (×0.5 of the rest) apart
}

TEST_CASE("rt_global_illumination: 1 and 2 threads give the same bits") {
    Scene scene = test::floorScene();
    scene.sceneUnitsPerMeter = 100.0;
    scene.meshes.push_back(test::sphere({0, 12, 0}, 10.0, 32, 0, 2));
    scene.lights.push_back(test::sun({0.3, -1, 0.2}));
    auto src = test::captureToMemory(scene, test::topCamera({}, 32));
    std::map<std::string, Texture> outs[2];
    for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        outs[threads - 1] = runGi(src, {{"samplesPerPixel", 2}, {"maxBounces", 2}});
    }
    for (const char* name : {"rt_global_illumination.diffuse", "rt_global_illumination.ao",
                             "rt_global_illumination.hitDistance"})
        for (int c = 0; c < outs[0].at(name).image().channelCount(); ++c)
            CHECK(test::sameBits(outs[0].at(name).image().plane(c), outs[1].at(name).image().plane(c)));
}

TEST_CASE("rt_global_illumination: paths traced in waves give the bits of one path at a time") {
    // A sphere on a floor under a sun with a source angle, a soft point light, a spot and a rect
    // light, the sky on for the bounce rays' misses: each path's closest hits, light samples of
    // every kind (a vector's lanes picking different lights; blocked by the sphere or not, behind
    // the rect light or outside the spot's cone or not) and bounces, and paths that end early (a
    // miss, a first hit beyond maxRayDistance) beside longer ones in the same wave. 70 pixels
    // leave a partial tile.
    Scene scene = test::floorScene();
    scene.sceneUnitsPerMeter = 100.0;
    scene.meshes.push_back(test::sphere({0, 12, 0}, 10.0, 32, 0, 2));
    scene.lights.push_back(test::sun({0.3, -1, 0.2}, 2.0f));
    scene.lights.push_back(test::spotLight({10, 40, -10}, {0, -1, 0.3}, 10.0f, 30.0f, 1.0f, 800.0f));
    scene.lights.push_back(test::pointLight({15, 30, 5}, 2.0f, 400.0f));
    scene.lights.push_back(test::rectLight({-20, 25, 0}, {5, 0, 0}, {0, 0, 5}, 50.0f));
    scene.environment.sky.enabled = true;
    const int n = 70;
    auto src = test::captureToMemory(scene, test::topCamera({}, n));
    for (const nlohmann::json& params :
         {nlohmann::json{{"samplesPerPixel", 3}, {"maxBounces", 3},
                         {"nextEventEstimationSamples", 3}, {"evalSkyLight", true}},
          nlohmann::json{{"samplesPerPixel", 2}, {"maxBounces", 2}, {"maxRayDistance", 15.0}},
          nlohmann::json{{"samplesPerPixel", 1}, {"maxBounces", 2},
                         {"nextEventEstimationSamples", 0}}}) {
        CAPTURE(params.dump());
        nlohmann::json one = params;
        one["waves"] = false;
        const auto single = runGi(src, one);
        // The waves' light samples run in SIMD lanes: on every instruction set the CPU has.
        test::onEveryLaneTarget([&] {
            const auto waves = runGi(src, params);
            const Plane& diffuse = waves.at("rt_global_illumination.diffuse").image().plane(0);
            int lit = 0;
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) lit += diffuse.at(x, y) > 0.0f;
            if (params.value("nextEventEstimationSamples", 2) > 0)
                CHECK(lit > 100);  // the sphere and the floor beside it gather light (not vacuous)
            for (const char* name : {"rt_global_illumination.diffuse", "rt_global_illumination.ao",
                                     "rt_global_illumination.hitDistance"})
                for (int c = 0; c < waves.at(name).image().channelCount(); ++c)
                    CHECK(test::sameBits(waves.at(name).image().plane(c),
                                         single.at(name).image().plane(c)));
        });
    }
}

TEST_CASE("rt_global_illumination: a screen percentage traces the top-left pixel of each block") {
    // Texel (x, y) at 1/k resolution is the full-resolution pass's pixel (k·x, k·y), bit for bit:
    // the same GBuffer pixel, the same random numbers (keyed by the pixel). 33 pixels leave a
    // partial last block, whose texel stands for its pixel clamped to the frame.
    Scene scene = test::floorScene();
    scene.sceneUnitsPerMeter = 100.0;
    scene.meshes.push_back(test::sphere({0, 12, 0}, 10.0, 32, 0, 2));
    scene.lights.push_back(test::sun({0.3, -1, 0.2}));
    const int n = 33;
    auto src = test::captureToMemory(scene, test::topCamera({}, n));
    const auto full = runGi(src, {{"samplesPerPixel", 2}, {"maxBounces", 2}});
    for (auto [percent, k] : {std::pair{50.0, 2}, {40.0, 2}, {33.0, 3}, {25.0, 4}}) {
        const auto part = runGi(src, {{"samplesPerPixel", 2}, {"maxBounces", 2},
                                      {"screenPercentage", percent}});
        for (const char* name : {"rt_global_illumination.diffuse", "rt_global_illumination.ao",
                                 "rt_global_illumination.hitDistance"}) {
            const Image& a = part.at(name).image();
            const Image& b = full.at(name).image();
            REQUIRE(a.width() == (n + k - 1) / k);
            REQUIRE(a.height() == (n + k - 1) / k);
            for (int c = 0; c < a.channelCount(); ++c)
                for (int y = 0; y < a.height(); ++y)
                    for (int x = 0; x < a.width(); ++x)
                        CHECK(a.plane(c).at(x, y) ==
                              b.plane(c).at(std::min(k * x, n - 1), std::min(k * y, n - 1)));
        }
    }
}

}  // namespace fp
