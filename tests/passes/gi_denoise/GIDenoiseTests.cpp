// gi_denoise (and the shared stages of the ray-traced denoisers, screenspace/SignalDenoiser): the
// variance of a noisy constant falls at least as a 17-sample mean's and further over frames, the
// mean stays, nothing crosses a crease, a hit at the surface itself allows no blur, and pixels
// with no ray are neither changed nor read.
#include "foundation/Error.h"
#include "tests/support/NoisySignal.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace fp;

namespace {

const std::vector<NodeDesc> kChain = {test::node(
    "gi_denoise", nlohmann::json::object(),
    {{"diffuse", "capture:Truth.NoisyDiffuse"},
     {"ao", "capture:Truth.NoisyAO"},
     {"hitDistance", "capture:Truth.HitDistance"}})};

std::vector<NodeDesc> chainWith(nlohmann::json params) {
    std::vector<NodeDesc> c = kChain;
    c[0].params = std::move(params);
    return c;
}

// A plane filling the view from above at an angle.
FrameCamera floorCamera(int w, int h) {
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 40, -10}, {0, 0, 10}, {0, 1, 0}, 60.0, w, h, 1.0);
    cam.previous = cam.current;
    return cam;
}

}  // namespace

TEST_SUITE("gi_denoise") {
TEST_CASE("the variance of a noisy constant falls below a 17-sample mean's; frames lower it further") {
    const int w = 96, h = 96;
    // Stages reach 8 (reconstruction) + 8 (pre-convolution) + 3 (history convolution) pixels:
    // statistics are taken where every tap stays on screen.
    const int border = 20;
    const Scene s = test::floorScene();
    const FrameCamera cam = floorCamera(w, h);
    HistoryStore history;
    std::mt19937 rng(11);
    double firstVar = 0, lastVar = 0;
    for (int frame = 1; frame <= 8; ++frame) {
        auto src = test::captureToMemory(s, cam, frame);
        src.info.firstInSequence = frame == 1;
        const Image diffuse = test::noisyConstant(w, h, {"R", "G", "B"}, rng);
        src.buffers["Truth.NoisyDiffuse"] = diffuse;
        src.buffers["Truth.NoisyAO"] = test::noisyConstant(w, h, {"Y"}, rng);
        src.buffers["Truth.HitDistance"] = Image(w, h, {"Y"}, 1e6f);  // far hits: the widest kernels
        const auto out = test::runChain(src, kChain, {"gi_denoise.diffuse", "gi_denoise.ao"}, &history);
        const auto in = test::windowStats(diffuse.plane(0), border);
        const auto got = test::windowStats(out.at("gi_denoise.diffuse").image().plane(0), border);
        // A normalised weighted mean moves the mean by no more than the input's own sampling
        // error (4σ/√n) beyond where the input's mean already is.
        CHECK(std::abs(got.mean - 0.5) <=
              4.0 * std::sqrt(in.variance / in.count) + std::abs(in.mean - 0.5));
        if (frame == 1) {
            // On one plane every tap weighs 1: the reconstruction alone is a mean of 17 pixels,
            // and the later stages only average further.
            CHECK(got.variance < in.variance / 17.0);
            firstVar = got.variance;
        }
        lastVar = got.variance;
    }
    // Seven frames of history: at least half again.
    CHECK(lastVar < firstVar / 2.0);
}

TEST_CASE("nothing crosses a crease: a floor of 1 beside a wall of 0 stays exactly so") {
    const int n = 48;
    const Scene s = test::floorAndWall();
    auto src = test::captureToMemory(s, test::wallCamera(n));
    const Plane& instance = src.buffers.at("InstanceId").plane(0);
    Image diffuse(n, n, {"R", "G", "B"});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c) diffuse.plane(c).at(x, y) = instance.at(x, y) == 1 ? 1.0f : 0.0f;
    src.buffers["Truth.NoisyDiffuse"] = diffuse;
    src.buffers["Truth.NoisyAO"] = Image(n, n, {"Y"}, 1.0f);
    src.buffers["Truth.HitDistance"] = Image(n, n, {"Y"}, 1e6f);
    const auto out = test::runChain(src, kChain, {"gi_denoise.diffuse"});
    // The floor's normal is perpendicular to the wall's: the bilateral weight is 0 across.
    int floorPixels = 0, wallPixels = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            CHECK(out.at("gi_denoise.diffuse").image().plane(0).at(x, y) ==
                  diffuse.plane(0).at(x, y));
            ++(instance.at(x, y) == 1 ? floorPixels : wallPixels);
        }
    CHECK(floorPixels > 100);
    CHECK(wallPixels > 100);
}

TEST_CASE("a hit at the surface itself allows no blur; pixels with no ray pass through unread") {
    const int w = 48, h = 48;
    const Scene s = test::floorScene();
    auto src = test::captureToMemory(s, floorCamera(w, h));
    std::mt19937 rng(5);
    const Image diffuse = test::noisyConstant(w, h, {"R", "G", "B"}, rng);
    src.buffers["Truth.NoisyDiffuse"] = diffuse;
    src.buffers["Truth.NoisyAO"] = test::noisyConstant(w, h, {"Y"}, rng);
    src.buffers["Truth.HitDistance"] = Image(w, h, {"Y"}, 0.0f);
    // Hit distance 0: the hit-sized stages have radius 0. (The history convolution's radius is
    // fixed in pixels, so it is turned off here.)
    auto out =
        test::runChain(src, chainWith({{"historyConvolutionSamples", 0}}), {"gi_denoise.diffuse"});
    for (int c = 0; c < 3; ++c)
        CHECK(test::sameBits(out.at("gi_denoise.diffuse").image().plane(c), diffuse.plane(c)));

    // Every other pixel carries no ray (hit distance −2) and a value of 1000: those keep it, and
    // no other pixel reads it (their values stay within the noise's range).
    Image hit(w, h, {"Y"}), loud = diffuse;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool noRay = (x + y) % 2 == 0;
            hit.plane(0).at(x, y) = noRay ? -2.0f : 1e6f;
            if (noRay)
                for (int c = 0; c < 3; ++c) loud.plane(c).at(x, y) = 1000.0f;
        }
    src.buffers["Truth.NoisyDiffuse"] = loud;
    src.buffers["Truth.HitDistance"] = hit;
    out = test::runChain(src, kChain, {"gi_denoise.diffuse"});
    const Plane& got = out.at("gi_denoise.diffuse").image().plane(0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if ((x + y) % 2 == 0)
                CHECK(got.at(x, y) == 1000.0f);
            else
                CHECK(got.at(x, y) <= 0.75f);
        }
}

TEST_CASE("planes of mismatched sizes are an error, not a read past the plane") {
    const int w = 32, h = 32;
    auto src = test::captureToMemory(test::floorScene(), floorCamera(w, h));
    std::mt19937 rng(9);
    src.buffers["Truth.NoisyDiffuse"] = test::noisyConstant(w, h, {"R", "G", "B"}, rng);
    src.buffers["Truth.NoisyAO"] = test::noisyConstant(w, h, {"Y"}, rng);
    src.buffers["Truth.HitDistance"] = Image(w / 2, h / 2, {"Y"}, 1e6f);
    CHECK_THROWS_WITH_AS(test::runChain(src, kChain, {"gi_denoise.diffuse"}),
                         doctest::Contains("hitDistance is 16×16 but the signal is 32×32"), Error);
    src.buffers["Truth.HitDistance"] = Image(w, h, {"Y"}, 1e6f);
    src.buffers["Truth.NoisyAO"] = test::noisyConstant(w / 2, h / 2, {"Y"}, rng);
    CHECK_THROWS_WITH_AS(test::runChain(src, kChain, {"gi_denoise.diffuse"}),
                         doctest::Contains("the signal's planes are 32×32 and 16×16"), Error);
    // A fifth of the frame is no screen percentage a ray-traced pass traces at.
    for (const char* name : {"Truth.NoisyDiffuse", "Truth.NoisyAO", "Truth.HitDistance"})
        src.buffers[name] = Image(7, 7, {"Y"}, 0.5f);
    CHECK_THROWS_WITH_AS(test::runChain(src, kChain, {"gi_denoise.diffuse"}),
                         doctest::Contains("neither the frame's 32×32 nor its 1/2, 1/3 or 1/4"), Error);
}

TEST_CASE("a signal traced at a lower screen percentage is upscaled to every pixel of the frame") {
    // A constant 0.5 traced at 1/2 and 1/3 of a 33×33 frame (17² and 11² texels): every frame
    // pixel on the plane gets exactly 0.5 (a normalised mean of equal values, scaled by a power
    // of two), the output has the frame's size, and denoiser 0 point-upsamples it.
    const int n = 33;
    auto src = test::captureToMemory(test::floorScene(), floorCamera(n, n));
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    for (int k : {2, 3}) {
        const int t = (n + k - 1) / k;
        Image diffuse(t, t, {"R", "G", "B"}, 0.5f);
        src.buffers["Truth.NoisyDiffuse"] = diffuse;
        src.buffers["Truth.NoisyAO"] = Image(t, t, {"Y"}, 0.5f);
        src.buffers["Truth.HitDistance"] = Image(t, t, {"Y"}, 1e6f);
        for (int denoiser : {1, 0}) {
            const auto out = test::runChain(src, chainWith({{"denoiser", denoiser}}),
                                            {"gi_denoise.diffuse", "gi_denoise.ao"});
            const Plane& got = out.at("gi_denoise.diffuse").image().plane(0);
            REQUIRE(got.width() == n);
            REQUIRE(got.height() == n);
            int surface = 0;
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x)
                    if (std::isfinite(depth.at(x, y))) {
                        CHECK(got.at(x, y) == 0.5f);
                        ++surface;
                    }
            CHECK(surface > n * n / 2);
        }
    }
}

TEST_CASE("denoiser 0 passes the raw signal through") {
    const int w = 32, h = 32;
    auto src = test::captureToMemory(test::floorScene(), floorCamera(w, h));
    std::mt19937 rng(3);
    const Image diffuse = test::noisyConstant(w, h, {"R", "G", "B"}, rng);
    const Image ao = test::noisyConstant(w, h, {"Y"}, rng);
    src.buffers["Truth.NoisyDiffuse"] = diffuse;
    src.buffers["Truth.NoisyAO"] = ao;
    src.buffers["Truth.HitDistance"] = Image(w, h, {"Y"}, 1e6f);
    const auto out = test::runChain(src, chainWith({{"denoiser", 0}}),
                                    {"gi_denoise.diffuse", "gi_denoise.ao"});
    for (int c = 0; c < 3; ++c)
        CHECK(test::sameBits(out.at("gi_denoise.diffuse").image().plane(c), diffuse.plane(c)));
    CHECK(test::sameBits(out.at("gi_denoise.ao").image().plane(0), ao.plane(0)));
}
}
