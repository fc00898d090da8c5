// Planar images: one block per image, planes one after the other (what lets the Python module
// hand the pixels out as one (channel, row, column) array without a copy), rows aligned.
#include "foundation/Image.h"

#include <doctest/doctest.h>

#include <cstdint>

namespace fp::test {

TEST_SUITE("foundation") {
    TEST_CASE("an image's planes lie one after the other in one aligned block") {
        const Image img(37, 5, {"R", "G", "B"}, 0.25f);
        const float* base = img.planarData();
        REQUIRE(base != nullptr);
        const std::ptrdiff_t stride = img.plane(0).stride();
        CHECK(stride >= 37);
        CHECK(stride % 16 == 0);  // rows start on 64-byte cache lines
        for (int c = 0; c < 3; ++c) {
            CHECK(img.plane(c).row(0) == base + c * stride * 5);
            CHECK(reinterpret_cast<std::uintptr_t>(img.plane(c).row(0)) % 64 == 0);
            CHECK(img.plane(c).at(36, 4) == 0.25f);
        }
    }

    TEST_CASE("a copy shares the pixels; a plane outlives its image") {
        Image a(8, 2, {"X", "Y"});
        const Image b = a;
        a.plane(1).at(3, 1) = 7.0f;
        CHECK(b.plane(1).at(3, 1) == 7.0f);
        Plane kept = a.plane(1);
        a = Image();
        CHECK(kept.at(3, 1) == 7.0f);
    }

    TEST_CASE("planes put together from other images are not one block") {
        Image a(4, 4, {"R", "G"});
        const Image other(4, 4, {"R"}, 1.0f);
        a.plane(1) = other.plane(0);
        CHECK(a.planarData() == nullptr);
        CHECK(Image(4, 4, {"Y"}).planarData() != nullptr);
        CHECK(Image().planarData() == nullptr);
    }
}

}  // namespace fp::test
