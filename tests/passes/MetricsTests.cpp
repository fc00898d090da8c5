// compare's metrics on hand-made images whose answers are worked out by hand.
#include "passes/core/Error.h"
#include "passes/metrics/ErrorMetrics.h"
#include "passes/metrics/Heatmap.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>

using namespace fp;

namespace {
Image fromValues(std::initializer_list<float> values, int w, int h) {
    Image img(w, h, {"Y"});
    auto it = values.begin();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.plane(0).at(x, y) = *it++;
    return img;
}
}  // namespace

TEST_SUITE("metrics") {

TEST_CASE("metrics of a = (1,2,3,4) against b = (1,1,1,1)") {
    const Image a = fromValues({1, 2, 3, 4}, 2, 2), b = fromValues({1, 1, 1, 1}, 2, 2);
    ErrorInputs in{&a, &b, nullptr, nullptr, 0.1};
    Image abs(2, 2, {"Y"});
    const ErrorStats s = measureError(in, &abs);
    // e = (0, 1, 2, 3)
    CHECK(s.pixels == 4);
    CHECK(s.rmse == doctest::Approx(std::sqrt(14.0 / 4)));
    CHECK(s.relMse == doctest::Approx(14.0 / 1.01 / 4));
    CHECK(s.smape == doctest::Approx((0.0 + 2.0 / 3 + 4.0 / 4 + 6.0 / 5) / 4));
    CHECK(s.mae == doctest::Approx(1.5));
    CHECK(s.bias == doctest::Approx(1.5));
    CHECK(s.maxError == doctest::Approx(3.0));
    CHECK(s.overTolerance == doctest::Approx(0.75));  // |e| > 0.1·1.01 for three pixels
    CHECK_FALSE(s.noiseRmse.has_value());
    CHECK(abs.plane(0).at(1, 1) == 3.0f);

    SUBCASE("a mask leaves pixels out") {
        const Image mask = fromValues({1, 1, 1, 0}, 2, 2);
        in.mask = &mask;
        const ErrorStats m = measureError(in, &abs);
        CHECK(m.pixels == 3);
        CHECK(m.maskedPixels == 1);
        CHECK(m.rmse == doctest::Approx(std::sqrt(5.0 / 3)));
        CHECK(m.maxError == doctest::Approx(2.0));
        CHECK(abs.plane(0).at(1, 1) == 0.0f);
    }
    SUBCASE("the reference's standard error gives the noise floor") {
        const Image sigma = fromValues({0.5f, 0.5f, 0.5f, 0.5f}, 2, 2);
        in.referenceStdErr = &sigma;
        const ErrorStats n = measureError(in);
        REQUIRE(n.noiseRmse.has_value());
        CHECK(*n.noiseRmse == doctest::Approx(0.5));
        CHECK_FALSE(n.noiseLimited());  // RMSE 1.87 > 2 × 0.5
    }
}

TEST_CASE("identical images have zero error; sign of the bias follows a − b") {
    const Image a = fromValues({0, 0.5f, 2, 8}, 2, 2), b = fromValues({0, 0.5f, 2, 8}, 2, 2);
    const ErrorStats s = measureError({&a, &b, nullptr, nullptr, 0.0});
    CHECK(s.rmse == 0.0);
    CHECK(s.smape == 0.0);  // 0/0 pixels count as no error
    CHECK(s.overTolerance == 0.0);
    const Image c = fromValues({0, 0.5f, 2, 7}, 2, 2);
    CHECK(measureError({&c, &b, nullptr, nullptr, 0.0}).bias == doctest::Approx(-0.25));
}

TEST_CASE("mismatched sizes and channel counts are errors") {
    const Image a(2, 2, {"Y"}), b(3, 2, {"Y"}), c(2, 2, {"R", "G", "B"});
    CHECK_THROWS_AS(measureError({&a, &b, nullptr, nullptr, 0.1}), Error);
    CHECK_THROWS_AS(measureError({&a, &c, nullptr, nullptr, 0.1}), Error);
}

TEST_CASE("a half-resolution result is measured point-upsampled") {
    // 2×2 against 3×3: full-res pixel (x, y) reads texel (x/2, y/2).
    const Image half = fromValues({1, 2, 3, 4}, 2, 2);
    const Image ref = fromValues({1, 1, 2, 1, 1, 2, 3, 3, 4}, 3, 3);
    const Image upsampled = fromValues({1, 1, 2, 1, 1, 2, 3, 3, 4}, 3, 3);
    ErrorInputs in{&half, &ref, nullptr, nullptr, 0.1};
    in.halfSource = true;
    Image abs(3, 3, {"Y"});
    const ErrorStats s = measureError(in, &abs);
    CHECK(s.pixels == 9);
    CHECK(s.rmse == 0.0);
    const Image off = fromValues({1, 1, 2, 1, 1, 2, 3, 3, 5}, 3, 3);
    in.reference = &off;
    const ErrorStats t = measureError(in, &abs);
    CHECK(t.maxError == 1.0);
    CHECK(abs.plane(0).at(2, 2) == 1.0f);
    CHECK(t.rmse == measureError({&upsampled, &off, nullptr, nullptr, 0.1}).rmse);
    // Only ⌈W/2⌉ × ⌈H/2⌉ is half of the reference.
    const Image wrong(1, 2, {"Y"});
    in.result = &wrong;
    CHECK_THROWS_AS(measureError(in), Error);
}

TEST_CASE("sky mask, relative noise and heat map scale") {
    const float inf = std::numeric_limits<float>::infinity();
    const Image depth = fromValues({1, inf, 50, 2000}, 2, 2);
    const Image mask = notSkyMask(depth, 1000.0f);
    CHECK(mask.plane(0).at(0, 0) == 1.0f);
    CHECK(mask.plane(0).at(1, 0) == 0.0f);
    CHECK(mask.plane(0).at(0, 1) == 1.0f);
    CHECK(mask.plane(0).at(1, 1) == 0.0f);

    const Image mean = fromValues({1, 2, 4, 0}, 2, 2), err = fromValues({0.1f, 0.1f, 0.1f, 1}, 2, 2);
    // Relative errors 0.1, 0.05, 0.025 (the zero-mean pixel does not count): median 0.05.
    CHECK(medianRelativeStdErr(mean, err) == doctest::Approx(0.05));

    Image ramp(100, 1, {"Y"});
    for (int x = 0; x < 100; ++x) ramp.plane(0).at(x, 0) = float(x + 1);
    CHECK(heatScale(ramp, nullptr) == 100.0f);  // index ⌊0.99·100⌋ = 99 of the sorted values
    const Image heat = heatmap(ramp, nullptr, 50.0f);
    // Saturated values take the top colour of the map, the smallest the bottom one.
    CHECK(heat.plane(1).at(99, 0) == heat.plane(1).at(60, 0));
    CHECK(heat.plane(1).at(0, 0) < heat.plane(1).at(99, 0));
}

}  // TEST_SUITE
