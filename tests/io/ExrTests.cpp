#include "io/CameraIO.h"
#include "io/ExrReader.h"
#include "io/ExrWriter.h"
#include "io/FramePattern.h"
#include "foundation/Error.h"
#include "tests/support/Scratch.h"

#include <OpenEXR/ImfHeader.h>
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

using namespace fp;
namespace fs = std::filesystem;

namespace {
std::string scratch(const std::string& name) { return test::scratchPath("", name); }

Image ramp(int w, int h, std::vector<std::string> channels, float scale) {
    Image img(w, h, channels);
    for (int c = 0; c < img.channelCount(); ++c)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) img.plane(c).at(x, y) = scale * (x + 7 * y + 100 * c) + 0.123f;
    return img;
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}
}  // namespace

TEST_SUITE("io") {

TEST_CASE("multi-layer EXR round trip: float exact, half within half precision") {
    const std::string path = scratch("roundtrip.exr");
    const Image depth = ramp(37, 21, {"Z"}, 1.37f);
    const Image color = ramp(37, 21, {"R", "G", "B"}, 0.01f);
    io::writeExr(path, {{"main", {{"SceneDepth", &depth, false}, {"SceneColor", &color, true}}}}, {});
    io::ExrReader r(path);
    CHECK(r.extent() == Extent{37, 21});
    CHECK(r.findChannel("SceneDepth.Z")->type == Imf::FLOAT);
    CHECK(r.findChannel("SceneColor.G")->type == Imf::HALF);
    const Image d = r.read({"SceneDepth.Z"}, {"Z"});
    const Image c = r.read({"SceneColor.R", "SceneColor.G", "SceneColor.B"}, {"R", "G", "B"});
    for (int y = 0; y < 21; ++y)
        for (int x = 0; x < 37; ++x) {
            CHECK(d.plane(0).at(x, y) == depth.plane(0).at(x, y));
            // Half has an 11-bit significand: relative error ≤ 2^-11.
            for (int ch = 0; ch < 3; ++ch)
                CHECK(c.plane(ch).at(x, y) ==
                      doctest::Approx(color.plane(ch).at(x, y)).epsilon(1.0 / 2048));
        }
}

TEST_CASE("lazy read decodes only the channels asked for") {
    const std::string path = scratch("lazy.exr");
    const Image a = ramp(8, 8, {"X", "Y", "Z"}, 1.0f), b = ramp(8, 8, {"R", "G", "B"}, 1.0f);
    io::writeExr(path, {{"p", {{"WorldNormal", &a, false}, {"BaseColor", &b, false}}}}, {});
    io::ExrReader r(path);
    CHECK(r.channels().size() == 6);
    const Image img = r.read({"BaseColor.G"}, {"G"});
    CHECK(img.channelCount() == 1);
    CHECK(r.readLog() == std::vector<std::string>{"BaseColor.G"});
    CHECK(img.plane(0).at(3, 2) == b.plane(1).at(3, 2));
}

TEST_CASE("hard case: half saturates HDR 1e5 instead of writing Inf") {
    const std::string path = scratch("hdr.exr");
    Image c(2, 1, {"R"});
    c.plane(0).at(0, 0) = 1e5f;
    c.plane(0).at(1, 0) = -1e5f;
    io::writeExr(path, {{"p", {{"SceneColor", &c, true}}}}, {});
    io::ExrReader r(path);
    const Image back = r.read({"SceneColor.R"}, {"R"});
    CHECK(back.plane(0).at(0, 0) == 65504.0f);
    CHECK(back.plane(0).at(1, 0) == -65504.0f);
}

TEST_CASE("rewriting the same data gives byte-identical files (no timestamp)") {
    const Image a = ramp(16, 16, {"Z"}, 3.0f);
    FrameCamera cam;
    cam.current = CameraView::lookAt({1, 2, 3}, {0, 0, 0}, {0, 1, 0}, 40, 16, 16, 10);
    io::ExrMetadata meta;
    meta.camera = cam;
    meta.frame = 7;
    io::writeExr(scratch("det1.exr"), {{"p", {{"SceneDepth", &a, false}}}}, meta);
    io::writeExr(scratch("det2.exr"), {{"p", {{"SceneDepth", &a, false}}}}, meta);
    CHECK(readBytes(scratch("det1.exr")) == readBytes(scratch("det2.exr")));
    // No temporary file is left behind.
    for (const auto& e : fs::directory_iterator(FP_TEST_SCRATCH))
        CHECK(e.path().extension() != ".tmp");
}

TEST_CASE("camera header attributes round-trip in double, and from worldToCamera/worldToNDC") {
    FrameCamera cam;
    cam.current = CameraView::lookAt({1e7 + 0.25, 3, -1e7}, {1e7 + 5, 1, -1e7 + 40}, {0, 1, 0},
                                     52.0, 64, 48, 10.0);
    cam.previous = cam.current;
    cam.previous->position.x -= 3.0;
    Imf::Header h(64, 48);
    io::writeCameraAttributes(h, cam);
    std::vector<std::string> assumed;
    const auto back = io::readCameraAttributes(h, {64, 48}, assumed);
    CHECK(assumed.empty());
    REQUIRE(back);
    CHECK(length(back->current.position - cam.current.position) < 1e-6);
    REQUIRE(back->previous);
    CHECK(back->previous->position.x == doctest::Approx(cam.previous->position.x).epsilon(1e-15));
    CHECK(back->current.fy == doctest::Approx(cam.current.fy));

    // Only the standard (float) attributes: intrinsics come back; the position is float-lossy.
    Imf::Header std(64, 48);
    io::writeCameraAttributes(std, cam);
    std.erase("framepass:worldToView");
    const auto fromStd = io::readCameraAttributes(std, {64, 48}, assumed);
    // worldToNDC carries no near plane: the assumed value is said.
    REQUIRE(assumed.size() == 1);
    CHECK(assumed[0].find("assumed 10 cm") != std::string::npos);
    REQUIRE(fromStd);
    CHECK(fromStd->current.fx == doctest::Approx(cam.current.fx).epsilon(1e-5));
    CHECK(fromStd->current.fy == doctest::Approx(cam.current.fy).epsilon(1e-5));
    CHECK(length(fromStd->current.forward - cam.current.forward) < 1e-5);
}

TEST_CASE("a truncated EXR is a clear error naming the file") {
    const std::string good = scratch("whole.exr"), bad = scratch("truncated.exr");
    const Image a = ramp(64, 64, {"Z"}, 1.0f);
    io::writeExr(good, {{"p", {{"SceneDepth", &a, false}}}}, {});
    const std::string bytes = readBytes(good);
    std::ofstream(bad, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    try {
        io::ExrReader r(bad);
        r.read({"SceneDepth.Z"}, {"Z"});
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("truncated.exr") != std::string::npos);
    }
}

TEST_CASE("frame patterns: #### and # are 4 digits, @@@ is 3, %05d is 5, inline ranges") {
    CHECK(io::FramePattern("a.####.exr").path(7) == "a.0007.exr");
    CHECK(io::FramePattern("a.#.exr").path(1001) == "a.1001.exr");
    CHECK(io::FramePattern("a.@@@.exr").path(7) == "a.007.exr");
    CHECK(io::FramePattern("a.%05d.exr").path(42) == "a.00042.exr");
    CHECK(io::FramePattern("plain.exr").path(42) == "plain.exr");
    const io::FramePattern inl("shot.1-3#.exr");
    CHECK(inl.inlineFrames() == "1-3");
    CHECK(inl.path(2) == "shot.0002.exr");
    CHECK(io::parseFrameSpec("3,4,10-20x5") == std::vector<int>{3, 4, 10, 15, 20});
    CHECK(io::parseFrameSpec("1-5y2") == std::vector<int>{2, 4});
    CHECK_THROWS_AS(io::parseFrameSpec("1-x"), UsageError);
}
}
