// ssgi_denoise on a noisy constant: the variance falls, the mean stays.
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace fp;

TEST_SUITE("ssgi_denoise") {
TEST_CASE("the denoiser lowers the variance of a noisy constant and keeps its mean") {
    // A plane filling the view; the denoiser's inputs are a constant 0.5 with uniform noise of
    // ±0.25 (variance 1/48) per pixel and frame, fed in as capture layers.
    const int w = 64, h = 48;
    Scene s = test::floorScene();
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 40, -10}, {0, 0, 10}, {0, 1, 0}, 60.0, w, h, 1.0);
    cam.previous = cam.current;
    const std::vector<NodeDesc> chain = {test::node(
        "ssgi_denoise", nlohmann::json::object(),
        {{"diffuse", "capture:Truth.NoisyDiffuse"}, {"ao", "capture:Truth.NoisyAO"}})};
    HistoryStore history;
    auto stats = [&](const Plane& p, double& mean, double& var) {
        double s1 = 0, s2 = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                s1 += p.at(x, y);
                s2 += double(p.at(x, y)) * p.at(x, y);
            }
        mean = s1 / (w * h);
        var = s2 / (w * h) - mean * mean;
    };
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> noise(0.25f, 0.75f);
    double firstVar = 0, lastVar = 0;
    for (int frame = 1; frame <= 8; ++frame) {
        auto src = test::captureToMemory(s, cam, frame);
        src.info.firstInSequence = frame == 1;
        Image diffuse(w, h, {"R", "G", "B"}), ao(w, h, {"Y"});
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                for (int c = 0; c < 3; ++c) diffuse.plane(c).at(x, y) = noise(rng);
                ao.plane(0).at(x, y) = noise(rng);
            }
        src.buffers["Truth.NoisyDiffuse"] = diffuse;
        src.buffers["Truth.NoisyAO"] = ao;
        const auto out = test::runChain(src, chain, {"ssgi_denoise.diffuse"}, &history);
        double inMean, inVar, outMean, outVar;
        stats(diffuse.plane(0), inMean, inVar);
        stats(out.at("ssgi_denoise.diffuse").image().plane(0), outMean, outVar);
        // The filter is a normalised weighted mean: the mean moves by no more than the input's
        // own sampling error, 4σ/√n.
        CHECK(std::abs(outMean - 0.5) <= 4.0 * std::sqrt(inVar / (w * h)) + std::abs(inMean - 0.5));
        if (frame == 1) firstVar = outVar;
        lastVar = outVar;
        // One frame: centre + up to 8 taps; even with half their weight lost to the bilateral
        // terms the variance falls below a third.
        if (frame == 1) CHECK(outVar < inVar / 3.0);
    }
    // Seven frames of history (a running mean over ~8 frames) lower it by at least half again.
    CHECK(lastVar < firstVar / 2.0);
}
}
