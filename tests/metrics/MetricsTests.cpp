// compare's metrics on hand-made images whose answers are worked out by hand.
#include "foundation/Error.h"
#include "metrics/ErrorDecomposition.h"
#include "metrics/ErrorMetrics.h"
#include "metrics/Heatmap.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>

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

TEST_CASE("a NaN or an infinity is an error of the largest kind, never within tolerance") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Image allNan = fromValues({nan, nan, nan, nan}, 2, 2), two = fromValues({2, 2, 2, 2}, 2, 2);
    Image abs(2, 2, {"Y"});
    const ErrorStats s = measureError({&allNan, &two, nullptr, nullptr, 0.1}, &abs);
    CHECK(s.pixels == 4);
    CHECK(s.nonFinitePixels == 4);
    CHECK(s.overTolerance == 1.0);
    CHECK(std::isinf(s.maxError));
    CHECK(std::isinf(abs.plane(0).at(0, 0)));
    // One bad pixel of each kind, in A and in B; the finite pixels keep their figures.
    const Image a = fromValues({1, nan, 3, 1}, 2, 2), b = fromValues({1, 1, 1, inf}, 2, 2);
    const ErrorStats m = measureError({&a, &b, nullptr, nullptr, 0.1});
    CHECK(m.nonFinitePixels == 2);
    CHECK(m.overTolerance == doctest::Approx(0.75));  // the two bad ones and |3 − 1|
    CHECK(m.rmse == doctest::Approx(std::sqrt(4.0 / 2)));  // over (1 − 1) and (3 − 1)
    CHECK(std::isinf(m.maxError));
    CHECK(m.toJson()["maxError"].is_null());  // JSON has no infinity
    CHECK(m.toJson()["nonFinitePixels"] == 2);
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


TEST_CASE("the error taken apart along a ladder: steps, telescoping biases, shares") {
    // Worked by hand. Result 3, middle rung 1, reference 0 on the masked-in pixels: d = (2, 1),
    // e = 3, so the shares are 2·3/9 and 1·3/9 and the biases 2 and 1 add up to 3. The masked-out
    // pixel holds values that would change every figure.
    const Image result = fromValues({3, 3, 3, 100}, 2, 2), middle = fromValues({1, 1, 1, -50}, 2, 2),
                reference = fromValues({0, 0, 0, 7}, 2, 2), mask = fromValues({1, 1, 1, 0}, 2, 2);
    const auto s = decomposeError({{&result}, {&middle}, {&reference}}, &mask);
    CHECK(s.values == 3);
    CHECK(s.rmse == doctest::Approx(3.0));
    CHECK(s.bias == doctest::Approx(3.0));
    REQUIRE(s.steps.size() == 2);
    CHECK(s.steps[0].rmse == doctest::Approx(2.0));
    CHECK(s.steps[1].rmse == doctest::Approx(1.0));
    CHECK(s.steps[0].bias == doctest::Approx(2.0));
    CHECK(s.steps[0].share == doctest::Approx(2.0 / 3.0));
    CHECK(s.steps[1].share == doctest::Approx(1.0 / 3.0));

    // A step that overshoots: result 1, middle 3, reference 0. d = (−2, 3), e = 1: the first step
    // cancels two of the second's three parts, shares −2 and 3.
    const Image one = fromValues({1, 1, 1, 1}, 2, 2), three = fromValues({3, 3, 3, 3}, 2, 2),
                zero = fromValues({0, 0, 0, 0}, 2, 2);
    const auto o = decomposeError({{&one}, {&three}, {&zero}}, nullptr);
    CHECK(o.steps[0].share == doctest::Approx(-2.0));
    CHECK(o.steps[1].share == doctest::Approx(3.0));
    CHECK(o.steps[0].rmse == doctest::Approx(2.0));

    // A half-resolution rung is read point-upsampled: the 1×1 rung 5 stands for all four pixels.
    const Image half = fromValues({5}, 1, 1);
    const auto h = decomposeError({{&half, true}, {&zero}}, nullptr);
    CHECK(h.values == 4);
    CHECK(h.bias == doctest::Approx(5.0));
    CHECK(h.steps[0].share == doctest::Approx(1.0));

    // Rungs that do not fit together are an error, not a guess.
    Image rgb(2, 2, {"R", "G", "B"});
    CHECK_THROWS_AS(decomposeError({{&rgb}, {&zero}}, nullptr), Error);
    CHECK_THROWS_AS(decomposeError({{&zero}}, nullptr), Error);
    CHECK_THROWS_AS(decomposeError({{&half}, {&zero}}, nullptr), Error);
}

TEST_CASE("on random images the biases telescope and the shares add up to one") {
    // Exactly so in real arithmetic; the bound is double rounding over 3·4096 values of order 1
    // (a relative 1e-16 per addition, far below 1e-12).
    std::mt19937 rng(7);
    std::normal_distribution<float> n(0.0f, 1.0f);
    std::vector<Image> rungs;
    for (int k = 0; k < 5; ++k) {
        Image img(64, 64, {"R", "G", "B"});
        for (int c = 0; c < 3; ++c)
            for (int y = 0; y < 64; ++y)
                for (int x = 0; x < 64; ++x)
                    img.plane(c).at(x, y) = n(rng) * float(k + 1) + 0.3f * float(k);
        rungs.push_back(std::move(img));
    }
    std::vector<LadderRung> ladder;
    for (const Image& r : rungs)
        ladder.push_back({&r});
    const auto s = decomposeError(ladder, nullptr);
    double biases = 0, shares = 0;
    for (const auto& step : s.steps) {
        biases += step.bias;
        shares += step.share;
    }
    CHECK(std::abs(biases - s.bias) < 1e-12);
    CHECK(std::abs(shares - 1.0) < 1e-12);
    // The total is what error_measure reports for the first rung against the last.
    ErrorInputs in{&rungs.front(), &rungs.back(), nullptr, nullptr, 0.1};
    const ErrorStats direct = measureError(in);
    CHECK(s.rmse == doctest::Approx(direct.rmse).epsilon(1e-12));
    CHECK(s.bias == doctest::Approx(direct.bias).epsilon(1e-12));
}

}  // TEST_SUITE
