// hybrid: rays that hit on screen are SSGI's, bit for bit; rays the screen cannot finish are
// traced through the scene, gathering (on a wall whose sunlit floor is off screen) the floor's
// analytic radiance, through SSGI's Karis weighting.
#include "tests/support/LaneTargets.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>

namespace fp {

namespace {

// hzb → prev_color_reduction → `type` (ssgi or hybrid), as the presets chain SSGI.
std::vector<NodeDesc> chain(const std::string& type, nlohmann::json params) {
    return {test::node("hzb"),
            test::node("prev_color_reduction", {}, {{"furthestHzb", "hzb.furthest"}}),
            test::node(type, std::move(params),
                       {{"furthestHzb", "hzb.furthest"}, {"reducedColor", "prev_color_reduction.color"}})};
}

std::map<std::string, Texture> run(test::MemorySource& src, const std::string& type,
                                   nlohmann::json params, std::map<std::string, uint64_t>* work = nullptr,
                                   bool hitDistance = false) {
    test::MemorySink sink;
    std::vector<std::string> outputs = {type + ".diffuse", type + ".ao", type + ".hitMask"};
    if (hitDistance) outputs.push_back(type + ".hitDistance");
    const FrameReport rep = executePlan(test::planFor(chain(type, std::move(params)), outputs), src, sink);
    if (work) *work = rep.passes.back().work;
    return sink.layers;
}

}  // namespace

TEST_CASE("hybrid: rays that hit on screen are SSGI's, bit for bit") {
    // The capture shows the glowing floor and wall; the scene the fallback traces is empty, so
    // every ray the screen cannot finish leaves it and adds nothing, as a miss adds nothing to
    // SSGI: the hybrid must then be SSGI's scalar reference exactly, at every pixel.
    const Scene scene = test::floorAndWall();
    auto src = test::captureToMemory(scene, test::wallCamera(48));
    const auto ssgi = run(src, "ssgi", {{"quality", 2}, {"lanes", false}});
    const Scene empty;
    src.sceneData = &empty;
    std::map<std::string, uint64_t> work;
    const auto hybrid = run(src, "hybrid", {{"quality", 2}}, &work);
    for (const char* port : {"diffuse", "ao", "hitMask"}) {
        const Image& a = hybrid.at(std::string("hybrid.") + port).image();
        const Image& b = ssgi.at(std::string("ssgi.") + port).image();
        for (int c = 0; c < a.channelCount(); ++c) CHECK(test::sameBits(a.plane(c), b.plane(c)));
    }
    CHECK(work.at("onScreenRays") + work.at("fallbackRays") == work.at("rays"));
    CHECK(work.at("onScreenRays") > 0);
    CHECK(work.at("fallbackHits") == 0);

    // With the scene itself the fallback finds what the screen did not: more hits, never fewer.
    auto withScene = test::captureToMemory(scene, test::wallCamera(48));
    const auto full = run(withScene, "hybrid", {{"quality", 2}}, &work);
    CHECK(work.at("fallbackHits") > 0);
    const Plane& ssgiMask = ssgi.at("ssgi.hitMask").image().plane(0);
    const Plane& hybridMask = full.at("hybrid.hitMask").image().plane(0);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) CHECK(hybridMask.at(x, y) >= ssgiMask.at(x, y));
}

TEST_CASE("hybrid: a wall whose sunlit floor is off screen gathers it through the scene") {
    // The floor y = 0 (albedo 0.5) under a sun straight down has radiance L = 0.5/π; the wall
    // x = 0 sees it over half its cosine-weighted hemisphere (algorithms §12.2's test). The camera
    // sees only the wall, so no ray can hit on screen (a plane does not meet itself): every ray
    // falls back, and half of them reach the floor. SSGI's resolve then gives, for k hits of n
    // rays, m/(1 − m) with m = (k/n)·L/(1 + L) (the Karis weighting undone on the mean, §4.8):
    // its expectation over k ~ Binomial(n, ½) is computed exactly below.
    Scene scene;
    scene.sceneUnitsPerMeter = 100.0;
    scene.materials.push_back(test::lambert(0.5f));
    scene.meshes.push_back(test::quad({-10000, 0, 0}, {0, 0, 1}, {1, 0, 0}, 10000, 0, 1));  // +y
    scene.meshes.push_back(test::quad({0, 10000, 0}, {0, 0, 1}, {0, 1, 0}, 10000, 0, 2));   // −x
    scene.lights.push_back(test::sun({0, -1, 0}));
    FrameCamera cam;
    cam.current = CameraView::lookAt({-20, 60, 0}, {0, 60, 0}, {0, 1, 0}, 20.0, 24, 24, 0.1);
    cam.previous = cam.current;
    auto src = test::captureToMemory(scene, cam);
    // Through Embree and through framepass's BVH (the GPU's code).
    for (const char* traversal : {"embree", "bvh"}) {
        INFO(traversal);
        std::map<std::string, uint64_t> work;
        // 32 rays a pixel
        const auto out = run(src, "hybrid", {{"quality", 4}, {"traversal", traversal}}, &work);
        // SSGI's tolerance lets a few rays grazing the wall count as hits on it (its last-frame
        // colour: 0, the wall is unlit); each such ray can take at most one floor ray's light away.
        const double caught = double(work.at("onScreenRays")) / double(work.at("rays"));
        CHECK(caught < 0.05);

        const int n = 32;
        const double L = 0.5 / kPi, w = L / (1.0 + L);
        double expected = 0, second = 0;
        for (int k = 0; k <= n; ++k) {
            const double p = std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) -
                                      std::lgamma(n - k + 1.0) - n * std::log(2.0));
            const double m = double(k) / n * w, f = m / (1.0 - m);
            expected += p * f;
            second += p * f * f;
        }
        const double sigmaPixel = std::sqrt(second - expected * expected);
        const Image& gi = out.at("hybrid.diffuse").image();
        double sum = 0;
        int pixels = 0;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                sum += gi.plane(0).at(x, y);
                ++pixels;
            }
        CAPTURE(expected);
        CAPTURE(caught);
        const double noise = 4.0 * sigmaPixel / std::sqrt(double(pixels));
        CHECK(sum / pixels < expected + noise);
        CHECK(sum / pixels > expected * (1.0 - 2.0 * caught) - noise);
        // Far from SSGI's own answer here: it sees no floor at all.
        CHECK(expected > 0.03);
    }
}

TEST_CASE("hybrid: continueOnScreen adds the hit's diffuse colour × the bounces after it") {
    // floorAndWall's surfaces glow but are black (albedo 0): a continued path adds 0 × its light,
    // so the result is the plain hybrid's, bit for bit, with every on-screen hit continued.
    Scene black = test::floorAndWall();
    black.lights.push_back(test::sun({0.3, -1, 0.2}));
    auto src = test::captureToMemory(black, test::wallCamera(32));
    std::map<std::string, uint64_t> plainWork, work;
    const auto plain = run(src, "hybrid", {{"quality", 1}, {"maxBounces", 3}}, &plainWork);
    const auto continued =
        run(src, "hybrid", {{"quality", 1}, {"maxBounces", 3}, {"continueOnScreen", true}}, &work);
    CHECK(work.at("onScreenRays") > 0);
    CHECK(work.at("continuedHits") == work.at("onScreenRays"));
    CHECK(work.at("sceneRays") > plainWork.at("sceneRays"));
    for (int c = 0; c < 3; ++c)
        CHECK(test::sameBits(continued.at("hybrid.diffuse").image().plane(c),
                             plain.at("hybrid.diffuse").image().plane(c)));

    // Grey (albedo 0.5) and sunlit: the continued paths bring light the screen's one bounce
    // lacks. They draw their own random numbers, so the fallback rays are the same and only
    // adds: no pixel loses light (Karis weighting and its resolve are increasing), the frame gains.
    Scene grey = black;
    grey.materials[0] = test::lambert(0.5f, test::kGlow);
    auto greySrc = test::captureToMemory(grey, test::wallCamera(32));
    const auto greyPlain = run(greySrc, "hybrid", {{"quality", 1}, {"maxBounces", 3}});
    const auto greyContinued =
        run(greySrc, "hybrid", {{"quality", 1}, {"maxBounces", 3}, {"continueOnScreen", true}});
    double gained = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const float a = greyPlain.at("hybrid.diffuse").image().plane(0).at(x, y);
            const float b = greyContinued.at("hybrid.diffuse").image().plane(0).at(x, y);
            CHECK(b >= a);
            gained += b - a;
        }
    CHECK(gained > 0.0);

    // One bounce leaves nothing to continue: the option changes nothing.
    const auto one = run(greySrc, "hybrid", {{"quality", 1}, {"continueOnScreen", true}}, &work);
    const auto oneBounce = run(greySrc, "hybrid", {{"quality", 1}});
    CHECK(work.at("continuedHits") == 0);
    CHECK(test::sameBits(one.at("hybrid.diffuse").image().plane(0),
                         oneBounce.at("hybrid.diffuse").image().plane(0)));
}

TEST_CASE("hybrid: scene paths traced in waves give the bits of each path where the march asks") {
    // A grey sphere on a grey floor under a sun with a source angle, a soft point light and a
    // rect light, seen from low down: rays that leave the screen or pass behind the sphere fall
    // back (some find the sky: nothing), on-screen hits continue; pixels with several paths of
    // each stream, beside pixels with none, in the same waves. 70 pixels leave a partial tile.
    Scene scene = test::floorScene();
    scene.sceneUnitsPerMeter = 100.0;
    scene.meshes.push_back(test::sphere({0, 12, 0}, 10.0, 32, 0, 2));
    scene.lights.push_back(test::sun({0.3, -1, 0.2}, 2.0f));
    scene.lights.push_back(test::pointLight({15, 30, 5}, 2.0f, 400.0f));
    scene.lights.push_back(test::rectLight({-20, 25, 0}, {5, 0, 0}, {0, 0, 5}, 50.0f));
    const int n = 70;
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 15, -45}, {0, 8, 10}, {0, 1, 0}, 60.0, n, n, 0.1);
    cam.previous = cam.current;
    auto src = test::captureToMemory(scene, cam);
    for (const auto& setting :
         {std::pair{nlohmann::json{{"quality", 1}, {"maxBounces", 3}, {"continueOnScreen", true}},
                    false},
          std::pair{nlohmann::json{{"quality", 2}, {"maxBounces", 2}, {"continueOnScreen", true},
                                   {"nextEventEstimationSamples", 3}},
                    true},
          std::pair{nlohmann::json{{"quality", 1}, {"maxBounces", 1}}, true}}) {
        const nlohmann::json& params = setting.first;
        const bool distance = setting.second;  // hitDistance requested too
        CAPTURE(params.dump());
        nlohmann::json one = params;
        one["waves"] = false;
        std::map<std::string, uint64_t> singleWork, wavesWork;
        const auto single = run(src, "hybrid", one, &singleWork, distance);
        // Not vacuous: paths of both kinds, that hit and that miss.
        CHECK(singleWork.at("fallbackRays") > uint64_t(n * n / 4));
        CHECK(singleWork.at("fallbackHits") > 0);
        CHECK(singleWork.at("fallbackHits") < singleWork.at("fallbackRays"));
        if (params.value("continueOnScreen", false))
            CHECK(singleWork.at("continuedHits") > uint64_t(n * n / 10));
        // The march and the waves' light samples run in SIMD lanes: on every instruction set
        // the CPU has.
        test::onEveryLaneTarget([&] {
            const auto waves = run(src, "hybrid", params, &wavesWork, distance);
            CHECK(wavesWork == singleWork);
            for (const auto& [name, texture] : single)
                for (int c = 0; c < texture.image().channelCount(); ++c)
                    CHECK(test::sameBits(waves.at(name).image().plane(c), texture.image().plane(c)));
        });
    }
}

}  // namespace fp
