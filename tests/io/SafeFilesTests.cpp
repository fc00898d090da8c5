// Files a farm can trust: outputs never over inputs, atomic text writes, stale temporaries
// removed, and no NaN written.
#include "io/ExrWriter.h"
#include "io/OutputWriter.h"
#include "io/SafeFiles.h"
#include "foundation/Error.h"
#include "tests/support/Scratch.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace fp;
namespace fs = std::filesystem;

namespace {
std::string scratch(const std::string& name) { return test::scratchPath("safe_files", name); }
}  // namespace

TEST_SUITE("io") {
    TEST_CASE("an output naming an input is refused, by identity or by path") {
        const std::string in = scratch("input.exr");
        std::ofstream(in) << "x";
        CHECK_THROWS_WITH_AS(io::refuseToOverwriteInputs(in, {"other", in}, "--report"),
                             doctest::Contains("that is an input of this command"), UsageError);
        // The same file by another spelling.
        const std::string other = (fs::path(in).parent_path() / "." / "input.exr").string();
        CHECK_THROWS_AS(io::refuseToOverwriteInputs(other, {in}, "-o"), UsageError);
        CHECK_NOTHROW(io::refuseToOverwriteInputs(scratch("fresh.json"), {in}, "--report"));
    }

    TEST_CASE("text is written atomically; a folder or /proc is not 'written'") {
        const std::string path = scratch("report.json");
        io::writeFileAtomically(path, "{}\n");
        io::writeFileAtomically(path, "{\"a\": 1}\n");
        std::ifstream in(path);
        std::string text((std::istreambuf_iterator<char>(in)), {});
        CHECK(text == "{\"a\": 1}\n");
        CHECK_THROWS_WITH_AS(io::writeFileAtomically(fs::path(path).parent_path().string(), "x"),
                             doctest::Contains("not a regular file"), Error);
        CHECK_THROWS_WITH_AS(io::checkWritable("/proc/version", "--report"),
                             doctest::Contains("cannot create a file in /proc"), UsageError);
    }

    TEST_CASE("temporaries of dead processes are removed, a live one's kept") {
        const std::string dir = (fs::path(scratch("x")).parent_path() / "temps").string();
        fs::remove_all(dir);
        fs::create_directories(dir);
        const std::string dead = dir + "/.final.0001.png.999999999.tmp";
        const std::string live = dir + fmt::format("/.final.0002.png.{}.tmp", ::getpid());
        const std::string other = dir + "/.hidden.tmp";  // no pid: not ours
        for (const auto& p : {dead, live, other}) std::ofstream(p) << "x";
        CHECK(io::removeStaleTemporaries(dir) == 1);
        CHECK(!fs::exists(dead));
        CHECK(fs::exists(live));
        CHECK(fs::exists(other));
    }

    TEST_CASE("a NaN in an output fails the frame naming the layer, and nothing is written") {
        io::OutputWriter::Options o;
        o.outputDir = (fs::path(scratch("x")).parent_path() / "nan").string();
        fs::remove_all(o.outputDir);
        fs::create_directories(o.outputDir);
        io::OutputWriter writer(o);
        Image img(4, 4, {"R", "G", "B"}, 0.5f);
        img.plane(1).at(2, 3) = NAN;
        const Texture t(img);
        OutputDesc out{"nan.####.exr", {"ssgi.diffuse"}, "/outputs/nan", false};
        FrameInfo frame;
        frame.number = 7;
        CHECK_THROWS_WITH_AS(
            writer.write(out, {{"ssgi.diffuse", &t, PortKind::Color}}, frame),
            doctest::Contains("frame 7: 'ssgi.diffuse' holds 1 NaN/Inf value(s); not written"),
            Error);
        CHECK(!fs::exists(writer.pathFor(out, 7)));
        // +inf is sky in depth-like data: allowed there.
        Image depth(4, 4, {"Z"}, INFINITY);
        const Texture d(depth);
        CHECK_NOTHROW(writer.write(out, {{"capture.depth", &d, PortKind::Data}}, frame));
    }
}
