#include "io/FramePattern.h"
#include "io/JsonFile.h"
#include "foundation/FloatToInt.h"
#include "foundation/Limits.h"
#include "foundation/Random.h"

#include <doctest/doctest.h>

#include <climits>
#include <cmath>
#include <limits>
#include <utility>

using namespace fp;

TEST_SUITE("io") {
    TEST_CASE("frame specs within the limits expand as oiiotool's; beyond them they are refused") {
        CHECK(io::parseFrameSpec("1-10x3") == std::vector<int>{1, 4, 7, 10});
        CHECK(io::parseFrameSpec("3,4,10-14x2") == std::vector<int>{3, 4, 10, 12, 14});
        CHECK(io::parseFrameSpec("-3--1") == std::vector<int>{-3, -2, -1});
        CHECK(io::parseFrameSpec("1-1000000").size() == 1'000'000);  // exactly the limit
        CHECK_THROWS_AS(io::parseFrameSpec("1-1000001"), UsageError);
        CHECK_THROWS_AS(io::parseFrameSpec("1-900000000x1000"), UsageError);  // span, not count
        CHECK_THROWS_AS(io::parseFrameSpec("-2147483648"), UsageError);
        CHECK_THROWS_AS(io::parseFrameSpec("1-10x0"), UsageError);
        CHECK_THROWS_AS(io::parseFrameSpec("1-"), UsageError);
        CHECK_THROWS_AS(io::parseFrameSpec("99999999999999999999"), UsageError);
    }

    TEST_CASE("frame tokens wider than 16 digits are refused; negative frames keep their sign") {
        CHECK(io::FramePattern("s.%016d.exr").path(7) == "s.0000000000000007.exr");
        CHECK(io::FramePattern("s.####.exr").path(-12) == "s.-0012.exr");
        CHECK(io::FramePattern("s.#.exr").path(INT_MIN + 1) == "s.-2147483647.exr");
        CHECK_THROWS_AS(io::FramePattern("s.%017d.exr"), UsageError);
        CHECK_THROWS_AS(io::FramePattern("s.%0999999999999999999d.exr"), UsageError);
        CHECK_THROWS_AS(io::FramePattern(std::string("s.") + std::string(17, '@') + ".exr"),
                        UsageError);
    }

    TEST_CASE("JSON deeper than the limit is a usage error; at the limit it parses") {
        const int d = limits::kMaxJsonDepth;
        CHECK(io::parseJsonLimited(std::string(d, '[') + std::string(d, ']'), "t").is_array());
        CHECK_THROWS_AS(io::parseJsonLimited(std::string(d + 1, '[') + std::string(d + 1, ']'),
                                             "t"),
                        UsageError);
        CHECK_THROWS_AS(io::parseJsonLimited(std::string(60000, '['), "t"), UsageError);
    }
}

TEST_SUITE("core") {
    TEST_CASE("float → int conversions clamp, and NaN and ±inf never reach the cast") {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        const double inf = std::numeric_limits<double>::infinity();
        CHECK(floorToInt(2.7, 0, 10) == 2);
        CHECK(floorToInt(-0.5, -1, 10) == -1);
        CHECK(floorToInt(nan, 0, 10) == 0);
        CHECK(floorToInt(inf, 0, 10) == 10);
        CHECK(floorToInt(-inf, 0, 10) == 0);
        CHECK(floorToInt(1e300, 0, 10) == 10);
        CHECK(truncToInt(-1.5, -5, 5) == -1);
        CHECK(truncToInt(nan, 0, 255) == 0);
        CHECK(truncToInt(3e9, 0, 255) == 255);
    }

    TEST_CASE("the float floorToInt (clamp, then one floor) gives the double one's integer") {
        // The HZB march floors in float without a branch; it must pick the texel the clamp-after-
        // floor definition picks, for every bound pair a march uses and for NaN and ±inf.
        const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                                  std::numeric_limits<float>::infinity(),
                                  -std::numeric_limits<float>::infinity(),
                                  -0.0f,
                                  1e30f,
                                  -1e30f,
                                  std::nextafter(0.0f, -1.0f),
                                  std::nextafter(7.0f, 0.0f),
                                  7.0f};
        const std::pair<int, int> bounds[] = {{0, 0}, {0, 7}, {-1, 8}, {0, 32767}, {-3, -1}};
        Rng rng(0, 0, 0, 17);
        for (const auto& [lo, hi] : bounds) {
            for (const float v : specials)
                CHECK(floorToInt(v, lo, hi) == floorToInt(double(v), lo, hi));
            for (int i = 0; i < 20000; ++i) {
                const float v = (rng.nextFloat() * 80.0f - 40.0f) * (i % 2 ? 1.0f : 1000.0f);
                REQUIRE(floorToInt(v, lo, hi) == floorToInt(double(v), lo, hi));
            }
        }
        CHECK(floorToInt(std::numeric_limits<float>::quiet_NaN(), 2, 9) == 2);
        CHECK(floorToInt(-0.5f, 0, 9) == 0);
        CHECK(floorToInt(8.999f, 0, 9) == 8);
        CHECK(floorToInt(9.5f, 0, 9) == 9);
    }
}
