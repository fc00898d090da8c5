// Planar images: one block per image, planes one after the other (what lets the Python module
// hand the pixels out as one (channel, row, column) array without a copy), rows aligned.
#include "foundation/Image.h"

#include <doctest/doctest.h>

#include <cstdint>
#include <memory>

#include <sys/resource.h>

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

    TEST_CASE("a chain's frames recycle the blocks of the frame before, though its outputs live on") {
        // One frame of a chain of ray-traced passes as the pool saw it at 1080p: the last frame's
        // output (b) is still held (by the sink, until this frame's replaces it) while this frame
        // makes its first images, so the frame needs one more block of b's size than it has alive
        // at its peak. A block made afresh faults its pages in when first written (the cost the
        // pool is there to save); a recycled one does not. Sizes of this test's own (the pool
        // keys its blocks by size): a 1080p plane and a few pages, and c past 32 MiB, the C
        // library's largest heap block, so that it maps and unmaps c from the kernel each time.
        constexpr std::size_t plane = std::size_t(1920) * 1080 * 4 + 4096 * 7;
        const std::size_t a = 3 * plane, b = plane, c = (std::size_t(32) << 20) + plane;
        const std::shared_ptr<void> capture = hostScratch(10 * plane);  // alive throughout
        std::shared_ptr<void> held = hostScratch(b);
        auto take = [](std::size_t bytes) {
            std::shared_ptr<void> block = hostScratch(bytes);
            auto* bytesOf = static_cast<volatile unsigned char*>(block.get());
            for (std::size_t at = 0; at < bytes; at += 4096) bytesOf[at] = 1;  // every page
            return block;
        };
        auto faults = [] {
            rusage usage{};
            getrusage(RUSAGE_SELF, &usage);
            return long(usage.ru_minflt);
        };
        for (int frame = 0; frame < 4; ++frame) {
            const long faultsBefore = faults();
            std::shared_ptr<void> gi = take(a), work1 = take(b), work2 = take(b);
            work1.reset();
            work2.reset();
            std::shared_ptr<void> reflection = take(c), output = take(b);
            gi.reset();
            reflection.reset();
            held = output;  // the sink lets the last frame's output go
            if (frame >= 2) {
                INFO("frame " << frame);
                // Not one block's pages (b's are 2,000 and more); a few faults are the test's own.
                CHECK(faults() - faultsBefore < long(b / 4096) / 4);
            }
        }
    }
}

}  // namespace fp::test
