// shadow_denoise: 1-spp soft shadows denoised come closer to converged ones.
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>

namespace fp {

TEST_CASE("the shadow denoiser brings 1-spp soft shadows closer to converged ones") {
    // A sphere light of radius 15 over a sphere and floor: wide penumbrae. The reference is the
    // same estimator at 64 rays per pixel (its noise, ≤ 0.5/8 per pixel, is 8× below 1 spp's).
    Light bulb;
    bulb.name = "bulb";
    bulb.position = {20, 80, -10};
    bulb.radius = 15.0f;
    bulb.intensity = 5000.0f;
    const Scene scene = test::sphereOverFloor({}, bulb);
    auto src = test::captureToMemory(scene, test::topCamera({}, 96));
    const auto noisy =
        test::runChain(src,
            {test::node("rt_shadows"), test::node("shadow_denoise", {},
                                                  {{"shadow", "rt_shadows.shadow"},
                                                   {"transmission", "rt_shadows.transmission"},
                                                   {"hitDistance", "rt_shadows.hitDistance"}})},
            {"rt_shadows.shadow", "shadow_denoise.shadow"});
    const auto converged =
        test::runChain(src, {test::node("rt_shadows", {{"samplesPerPixel", 64}})}, {"rt_shadows.shadow"});
    const auto rawOnly = test::runChain(src, {test::node("rt_shadows")}, {"rt_shadows.shadow"});
    const Plane& raw = noisy.at("rt_shadows.shadow").image().plane(0);
    const Plane& den = noisy.at("shadow_denoise.shadow").image().plane(0);
    const Plane& ref = converged.at("rt_shadows.shadow").image().plane(0);
    // The denoiser filters a copy: its input is what rt_shadows wrote on its own.
    CHECK(test::sameBits(raw, rawOnly.at("rt_shadows.shadow").image().plane(0)));
    double eRaw = 0, eDen = 0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x) {
            eRaw += std::pow(raw.at(x, y) - ref.at(x, y), 2.0);
            eDen += std::pow(den.at(x, y) - ref.at(x, y), 2.0);
        }
    MESSAGE("squared error raw " << eRaw << ", denoised " << eDen);
    CHECK(eDen < 0.5 * eRaw);
}


}  // namespace fp
