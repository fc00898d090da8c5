// display's GPU form checked on the CPU: the half-float indexing it rests on, and the baked OCIO
// transform against OCIO's own CPU processor (DisplayKernel.h).
#include "foundation/HalfFloat.h"
#include "passes/display/DisplayKernel.h"
#include "color/DisplayTransform.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace fp {
namespace {

TEST_CASE("display table: every finite half is found again, in order") {
    float previous = -1.0f;
    int wrong = 0;
    for (uint32_t h = 0; h <= display::kMaxFiniteHalf; ++h) {
        const float v = display::halfValue(h);
        const bool ok = v > previous && roundToHalf(v) == v &&  // increasing, and a half
                        display::halfBitsBelow(v) == h &&
                        // just below a half: the one before it
                        (h == 0 || display::halfBitsBelow(std::nextafter(v, 0.0f)) == h - 1);
        wrong += ok ? 0 : 1;
        previous = v;
    }
    CHECK(wrong == 0);
    CHECK(display::halfValue(display::kMaxFiniteHalf) == 65504.0f);
    CHECK(display::halfBitsBelow(1e30f) == display::kMaxFiniteHalf);
}

TEST_CASE("display table: the baked sRGB view matches OCIO's CPU processor") {
    test::MemorySource src;
    const auto config = src.colorConfig();
    const DisplayTransform transform(config, "scene_linear", "", "", 0.0f, true);
    const auto table = transform.halfLut();
    REQUIRE(table);
    // The same processor applied directly to values between the table's nodes.
    const std::string display = config->getDefaultDisplay();
    auto dv = OCIO_NAMESPACE::DisplayViewTransform::Create();
    dv->setSrc("scene_linear");
    dv->setDisplay(display.c_str());
    dv->setView(config->getDefaultView(display.c_str()));
    const auto cpu = config->getProcessor(dv)->getDefaultCPUProcessor();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> exponent(-20.0f, 3.0f);
    double worst = 0.0;
    float worstAt = 0.0f;
    for (int i = 0; i < 200000; ++i) {
        const float v = std::exp2(exponent(rng)) * (i % 8 == 0 ? -1.0f : 1.0f);
        float rgb[3] = {v, v, v};
        cpu->applyRGB(rgb);
        for (int c = 0; c < 3; ++c) {
            // What the preview keeps: [0, 1].
            const float baked =
                std::clamp(display::halfLutLookup(viewOf(table->plane(c)), v), 0.0f, 1.0f);
            const double d = std::fabs(double(baked) - double(std::clamp(rgb[c], 0.0f, 1.0f)));
            if (d > worst) {
                worst = d;
                worstAt = v;
            }
        }
    }
    // Linear interpolation between halves (relative step h = 2⁻¹⁰) of 1.055·x^(1/2.4) − 0.055
    // errs by at most h²x²/8·|f''(x)| = 2⁻²³·0.2565·x^0.417 ≤ 3.1e-8 on [0, 1], the displayed
    // range; the lookup's own arithmetic adds a few float steps of 1.2e-7. Measured: 1.8e-7.
    INFO("largest difference " << worst << " at " << worstAt);
    CHECK(worst <= 4e-7);
}

}  // namespace
}  // namespace fp
