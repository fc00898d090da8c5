// ao_denoise: the AO preset of the ray-traced denoisers (the stages themselves are tested through
// gi_denoise): a noisy AO mask on a plane loses variance and keeps its mean.
#include "tests/support/NoisySignal.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace fp;

TEST_CASE("ao_denoise lowers the variance of a noisy AO mask and keeps its mean") {
    const int w = 96, h = 96, border = 40;  // 8 + 2 × 8 + 7 pixels of kernels, and a margin
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 40, -10}, {0, 0, 10}, {0, 1, 0}, 60.0, w, h, 1.0);
    cam.previous = cam.current;
    auto src = test::captureToMemory(test::floorScene(), cam);
    std::mt19937 rng(17);
    const Image ao = test::noisyConstant(w, h, {"Y"}, rng);
    const Image hit(w, h, {"Y"}, 1e6f);  // nothing near: the widest kernels
    src.buffers["Truth.NoisyAO"] = ao;
    src.buffers["Truth.HitDistance"] = hit;
    const auto out = test::runChain(
        src,
        {test::node("ao_denoise", nlohmann::json::object(),
                    {{"ao", "capture:Truth.NoisyAO"}, {"hitDistance", "capture:Truth.HitDistance"}})},
        {"ao_denoise.ao"});
    const auto in = test::windowStats(ao.plane(0), border);
    const auto got = test::windowStats(out.at("ao_denoise.ao").image().plane(0), border);
    CHECK(std::abs(got.mean - 0.5) <= 4.0 * std::sqrt(in.variance / in.count) + std::abs(in.mean - 0.5));
    // A 16-tap reconstruction on one plane is a 17-pixel mean; two pre-convolutions and the
    // history convolution only average further.
    CHECK(got.variance < in.variance / 17.0);
}
