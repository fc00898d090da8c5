// reflection_denoise: its kernels are the reflected lobe's footprint (hit distance × roughness²),
// so a mirror's reflections come through untouched and a rough floor's noisy ones lose variance.
#include "tests/support/NoisySignal.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace fp;

namespace {

std::map<std::string, Texture> denoiseReflections(float roughness, const Image& reflection) {
    const int w = reflection.width(), h = reflection.height();
    Scene s = test::floorScene();
    s.materials[0].roughness = roughness;
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 40, -10}, {0, 0, 10}, {0, 1, 0}, 60.0, w, h, 1.0);
    cam.previous = cam.current;
    auto src = test::captureToMemory(s, cam);
    const Image hit(w, h, {"Y"}, 1e6f);  // nothing near: the widest kernels
    src.buffers["Truth.NoisyReflection"] = reflection;
    src.buffers["Truth.HitDistance"] = hit;
    return test::runChain(src,
                          {test::node("reflection_denoise", nlohmann::json::object(),
                                      {{"reflection", "capture:Truth.NoisyReflection"},
                                       {"hitDistance", "capture:Truth.HitDistance"}})},
                          {"reflection_denoise.reflection"});
}

}  // namespace

TEST_CASE("reflection_denoise: a mirror's reflections come through bit for bit") {
    std::mt19937 rng(23);
    const Image reflection = test::noisyConstant(48, 48, {"R", "G", "B", "A"}, rng);
    const auto out = denoiseReflections(0.0f, reflection);
    for (int c = 0; c < 4; ++c)
        CHECK(test::sameBits(out.at("reflection_denoise.reflection").image().plane(c),
                             reflection.plane(c)));
}

TEST_CASE("reflection_denoise: a rough floor's noisy reflections lose variance, keep their mean") {
    std::mt19937 rng(29);
    const int border = 20;
    const Image reflection = test::noisyConstant(96, 96, {"R", "G", "B", "A"}, rng);
    const auto out = denoiseReflections(1.0f, reflection);
    const auto in = test::windowStats(reflection.plane(0), border);
    const auto got =
        test::windowStats(out.at("reflection_denoise.reflection").image().plane(0), border);
    CHECK(std::abs(got.mean - 0.5) <= 4.0 * std::sqrt(in.variance / in.count) + std::abs(in.mean - 0.5));
    // An 8-tap reconstruction on one plane of one roughness is a 9-pixel mean.
    CHECK(got.variance < in.variance / 9.0);
}
