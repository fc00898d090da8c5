// Reading a sequence's next frame ahead (io/CaptureReadAhead.h): the buffers come back with the
// bits and the read log a frame reading them itself gets, a read-ahead of another frame is not
// handed out, and a broken frame's error is met again where the frame itself reads.
#include "io/CaptureReadAhead.h"
#include "io/CaptureSource.h"
#include "io/ExrWriter.h"
#include "foundation/Error.h"
#include "reference/GBufferRenderer.h"
#include "tests/support/Scratch.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

using namespace fp;

namespace {

std::string scratch(const std::string& name) { return test::scratchPath("read_ahead", name); }

// A capture of the floor-and-wall scene as `framepass capture` writes it: one part a buffer.
void writeCaptureFrame(const std::string& path, int64_t frame) {
    const Scene scene = test::floorAndWall();
    const FrameCamera camera = test::wallCamera(24);
    CaptureSettings settings;
    settings.frame = frame;
    settings.lightSamples = 1;
    const CaptureResult result = GBufferRenderer(scene, camera, settings).render();
    std::vector<io::ExrPart> parts;
    for (const auto& [name, image] : result.buffers) parts.push_back({name, {{name, &image}}});
    io::ExrMetadata meta;
    meta.camera = camera;
    meta.frame = frame;
    io::writeExr(path, parts, meta);
}

io::CaptureOptions optionsFor(const std::string& path, int64_t frame) {
    io::CaptureOptions o;
    o.path = path;
    o.frame = frame;
    return o;
}

const std::vector<CaptureRead> kReads = {{"SceneDepth", 1}, {"WorldNormal", 3}, {"BaseColor", 3}};

bool sameBits(const Image& a, const Image& b) {
    if (a.width() != b.width() || a.height() != b.height() || a.channelCount() != b.channelCount())
        return false;
    for (int c = 0; c < a.channelCount(); ++c)
        if (!test::sameBits(a.plane(c), b.plane(c))) return false;
    return true;
}

}  // namespace

TEST_SUITE("read ahead") {
    TEST_CASE("a frame read ahead gives the bits, notes and read log of a frame read in place") {
        const std::string f2 = scratch("seq.0002.exr");
        writeCaptureFrame(f2, 2);
        const auto profile = io::CaptureProfile::load("canonical");

        io::CaptureSource direct(optionsFor(f2, 2), profile);
        io::CaptureReadAhead ahead;
        ahead.start(optionsFor(f2, 2), profile, kReads);
        auto read = ahead.take(2);
        REQUIRE(read);
        for (const auto& r : kReads)
            CHECK(sameBits(read->loadBuffer(r.buffer, r.channels).image(),
                           direct.loadBuffer(r.buffer, r.channels).image()));
        CHECK(read->readLog() == direct.readLog());
        CHECK(read->notes() == direct.notes());
        // A buffer asked again (or with other channels) is read again, not handed out twice.
        CHECK(sameBits(read->loadBuffer("SceneDepth", 1).image(),
                       direct.loadBuffer("SceneDepth", 1).image()));
        // A sequence's first unless its driver says otherwise (app/FrameDriver's FrameView).
        CHECK(read->frameInfo().firstInSequence);
        CHECK(read->frameInfo().number == 2);
    }

    TEST_CASE("a read-ahead of another frame, or none, hands out nothing") {
        const std::string f3 = scratch("seq.0003.exr");
        writeCaptureFrame(f3, 3);
        const auto profile = io::CaptureProfile::load("canonical");
        io::CaptureReadAhead ahead;
        CHECK_FALSE(ahead.take(3));  // nothing started
        ahead.start(optionsFor(f3, 3), profile, kReads);
        CHECK_FALSE(ahead.take(4));  // the run moved on to another frame: dropped
        CHECK_FALSE(ahead.take(3));  // and not kept
    }

    TEST_CASE("a broken frame read ahead fails where the frame reads it, with the same error") {
        const std::string good = scratch("good.0005.exr"), missing = scratch("missing.0005.exr"),
                          cut = scratch("cut.0005.exr"), nan = scratch("nan.0005.exr");
        writeCaptureFrame(good, 5);
        std::filesystem::remove(missing);
        {
            std::ifstream in(good, std::ios::binary);
            std::string bytes((std::istreambuf_iterator<char>(in)), {});
            std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
        }
        const auto profile = io::CaptureProfile::load("canonical");
        io::CaptureReadAhead ahead;
        // Not opened: nothing handed out; the frame opens the file itself and says why.
        for (const std::string& path : {missing, cut}) {
            CAPTURE(path);
            ahead.start(optionsFor(path, 5), profile, kReads);
            CHECK_FALSE(ahead.take(5));
            CHECK_THROWS_AS(
                [&] {
                    io::CaptureSource direct(optionsFor(path, 5), profile);
                    direct.frameInfo();
                    for (const auto& r : kReads) direct.loadBuffer(r.buffer, r.channels);
                }(),
                Error);
        }

        // Opened, but a buffer is refused (--strict and a NaN in the normals): the buffers before
        // it come from the read-ahead, and the bad one fails when the frame asks for it.
        {
            const Scene scene = test::floorAndWall();
            const FrameCamera camera = test::wallCamera(24);
            CaptureSettings settings;
            settings.lightSamples = 1;
            CaptureResult result = GBufferRenderer(scene, camera, settings).render();
            result.buffers.at("WorldNormal").plane(0).at(3, 4) = std::nanf("");
            std::vector<io::ExrPart> parts;
            for (const auto& [name, image] : result.buffers) parts.push_back({name, {{name, &image}}});
            io::ExrMetadata meta;
            meta.camera = camera;
            meta.frame = 5;
            io::writeExr(nan, parts, meta);
        }
        io::CaptureOptions strict = optionsFor(nan, 5);
        strict.strict = true;
        std::string inPlace;
        {
            io::CaptureSource direct(strict, profile);
            CHECK_NOTHROW(direct.loadBuffer("SceneDepth", 1));
            try {
                direct.loadBuffer("WorldNormal", 3);
            } catch (const Error& e) {
                inPlace = e.what();
            }
        }
        REQUIRE(inPlace.find("--strict") != std::string::npos);
        ahead.start(strict, profile, kReads);
        auto read = ahead.take(5);
        REQUIRE(read);
        CHECK_NOTHROW(read->loadBuffer("SceneDepth", 1));
        std::string fromAhead;
        try {
            read->loadBuffer("WorldNormal", 3);
        } catch (const Error& e) {
            fromAhead = e.what();
        }
        CHECK(fromAhead == inPlace);
        CHECK(read->sanitized().total() == 0);  // the refused buffer counted nowhere
    }
}
