// Capture profiles as data: the built-in tables, what a mapping can say, the checks that turn a
// wrong profile into an error, and captures written in Unreal's layouts (Movie Render Queue,
// buffer-visualisation dumps) read back with their cameras.
#include "io/CameraIO.h"
#include "io/CaptureFiles.h"
#include "io/CaptureProfile.h"
#include "io/CaptureSource.h"
#include "io/ExrWriter.h"
#include "foundation/Error.h"
#include "tests/support/Scratch.h"

#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenImageIO/imageio.h>
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace fp;
namespace fs = std::filesystem;

namespace {

std::string scratch(const std::string& name) { return test::scratchPath("profiles", name); }

// One EXR through OpenImageIO, as Unreal's writers lay it out: `channels` in the order given
// (BGRA sources give B, G, R, A), every channel `type`, string attributes as MRQ writes them.
void writeExr(const std::string& path, int w, int h, const std::vector<std::string>& channels,
              const std::function<float(int x, int y, int c)>& value, OIIO::TypeDesc type,
              const std::map<std::string, std::string>& attributes = {}) {
    OIIO::ImageSpec spec(w, h, int(channels.size()), type);
    spec.channelnames = channels;
    spec.alpha_channel = -1;
    for (const auto& [k, v] : attributes) spec.attribute(k, v);
    std::vector<float> pixels(std::size_t(w) * h * channels.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (std::size_t c = 0; c < channels.size(); ++c)
                pixels[(std::size_t(y) * w + x) * channels.size() + c] = value(x, y, int(c));
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    REQUIRE(out->open(path, spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    out->close();
}

// Layer "<name>" as B, G, R, A channels holding (r, g, b, 1).
std::vector<std::string> bgra(const std::string& layer) {
    const std::string p = layer.empty() ? "" : layer + ".";
    return {p + "B", p + "G", p + "R", p + "A"};
}

bool hasNote(const std::vector<std::string>& notes, const std::string& text) {
    for (const auto& n : notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

constexpr int kW = 8, kH = 6;

// An MRQ frame: FinalImage unnamed, depth from MovieRenderQueue_WorldDepth, FP_ materials, all
// layers of camera `cam` (suffix _<cam>), half float, written B, G, R, A.
void writeMrqFrame(const std::string& path, float colour, const std::vector<std::string>& cams,
                   const std::map<std::string, std::string>& camera) {
    std::vector<std::string> channels = bgra("");
    for (const auto& cam : cams)
        for (const std::string layer :
             {"FinalImageMovieRenderQueue_WorldDepth", "FinalImageFP_WorldNormal",
              "FinalImageFP_BaseColor"})
            for (const auto& c : bgra(layer + "_" + cam)) channels.push_back(c);
    writeExr(path, kW, kH, channels,
             [&](int x, int y, int c) -> float {
                 const std::string& name = channels[std::size_t(c)];
                 const char comp = name.back();
                 if (comp == 'A') return 1.0f;
                 const int rgb = comp == 'R' ? 0 : comp == 'G' ? 1 : 2;
                 if (name.find("WorldDepth") != std::string::npos)  // cm; one sky pixel (+inf)
                     return x == 0 && y == 0 ? INFINITY : float(100 + 10 * x + y);
                 if (name.find("WorldNormal") != std::string::npos)  // +Z up, Unreal's axes
                     return rgb == 2 ? 1.0f : 0.0f;
                 if (name.find("BaseColor") != std::string::npos) return 0.25f * (rgb + 1);
                 return colour * (rgb + 1);  // FinalImage
             },
             OIIO::TypeDesc::HALF, camera);
}

const std::map<std::string, std::string> kMrqCamera = {
    {"unreal/camera/curPos/x", "100"},  {"unreal/camera/curPos/y", "200"},
    {"unreal/camera/curPos/z", "50"},   {"unreal/camera/curRot/pitch", "-10"},
    {"unreal/camera/curRot/yaw", "30"}, {"unreal/camera/curRot/roll", "0"},
    {"unreal/camera/prevPos/x", "90"},  {"unreal/camera/prevPos/y", "200"},
    {"unreal/camera/prevPos/z", "50"},  {"unreal/camera/prevRot/pitch", "-10"},
    {"unreal/camera/prevRot/yaw", "30"}, {"unreal/camera/prevRot/roll", "0"},
    {"unreal/camera/FinalImage/fov", "90"}, {"unreal/camera/FinalImage/sensorWidth", "36"}};

}  // namespace

TEST_SUITE("io") {
    TEST_CASE("every built-in profile is a table under configs/profiles and loads") {
        const auto names = io::CaptureProfile::builtinNames();
        for (const std::string n : {"canonical", "ue-mrq", "ue-bufvis"}) {
            CAPTURE(n);
            CHECK(std::find(names.begin(), names.end(), n) != names.end());
            CHECK(io::CaptureProfile::load(n).name() == n);
        }
        const auto canonical = io::CaptureProfile::load("canonical");
        REQUIRE(canonical.mappings("WorldNormal"));
        CHECK(canonical.mappings("WorldNormal")->front().groups.front() ==
              std::vector<std::string>{"WorldNormal.X", "WorldNormal.Y", "WorldNormal.Z"});
        CHECK_THROWS_WITH_AS(io::CaptureProfile::load("blendr2"),
                             doctest::Contains("unknown capture profile 'blendr2'"), UsageError);
        CHECK_THROWS_WITH_AS(io::CaptureProfile::load("canonicl"),
                             doctest::Contains("did you mean 'canonical'?"), UsageError);
    }

    TEST_CASE("a profile mistake is an error with its JSON pointer, in every build type") {
        // The trap of the old assert: WorldNormal mapped to two channels.
        CHECK(errorOf([] {
                  io::CaptureProfile::fromJson(
                      {{"buffers", {{"WorldNormal", {{"channels", {"N.X", "N.Y"}}}}}}},
                      "cfg.json: /profile");
              }) == "cfg.json: /profile/buffers/WorldNormal/channels: WorldNormal has 3 channels "
                    "(X, Y, Z); this lists 2 (N.X, N.Y)");
        // The shorthand list of channels is checked the same way.
        CHECK_THROWS_WITH_AS(
            io::CaptureProfile::fromJson({{"buffers", {{"Velocity", {"V.X"}}}}}, "/profile"),
            doctest::Contains("Velocity has 2 channels"), UsageError);
        CHECK_THROWS_WITH_AS(io::CaptureProfile::fromJson(
                                 {{"buffers", {{"BaseColor", {{"chanels", {"a", "b", "c"}}}}}}}, "/p"),
                             doctest::Contains("did you mean 'channels'?"), UsageError);
        CHECK_THROWS_WITH_AS(
            io::CaptureProfile::fromJson(
                {{"buffers", {{"BaseColor", {{"channels", {"a", "b", "c"}}, {"skyAbove", 5}}}}}},
                "/p"),
            doctest::Contains("/p/buffers/BaseColor/skyAbove: only depth buffers"), UsageError);
        CHECK_THROWS_WITH_AS(
            io::CaptureProfile::fromJson(
                {{"buffers", {{"SceneDepth", {{"constant", 1}, {"channels", {"Z"}}}}}}}, "/p"),
            doctest::Contains("exactly one of"), UsageError);
        CHECK_THROWS_WITH_AS(
            io::CaptureProfile::fromJson(
                {{"base", "ue-mrq"}, {"buffers", {{"SceneColor", {{"previousFrame", "PrevSceneColor"}}}}}},
                "/p"),
            doctest::Contains("is itself taken from the previous frame (/p/buffers/SceneColor)"),
            UsageError);
        CHECK_THROWS_WITH_AS(
            io::CaptureProfile::fromJson({{"buffers", {{"Metallic", {{"constant", NAN}}}}}}, "/p"),
            doctest::Contains("/p/buffers/Metallic/constant: must be finite"), UsageError);
        CHECK_THROWS_WITH_AS(
            io::CaptureProfile::fromJson({{"base", "ue-mrq"}, {"buffers", {{"BaseColor", {{"file", "X"}, {"channels", {"R", "G", "B"}}}}}}}, "/p"),
            doctest::Contains("'file' needs the profile's \"files\" pattern"), UsageError);
    }

    TEST_CASE("a mapping swizzles, flips, scales, sums, thresholds sky and fills constants") {
        const std::string path = scratch("mapped.exr");
        const std::vector<std::string> ch = {"d.Z", "n.X", "n.Y", "n.Z", "e.R", "e.G", "e.B",
                                             "s.R", "s.G", "s.B"};
        writeExr(path, 4, 2, ch,
                 [&](int x, int, int c) -> float {
                     switch (c) {
                         case 0: return x == 3 ? 1e10f : 1.5f + x;  // metres; 1e10 = background
                         case 1: return 0.0f;                        // Blender-like Z-up normal
                         case 2: return 0.0f;
                         case 3: return 1.0f;
                         default: return c < 7 ? 0.5f : 0.25f;
                     }
                 },
                 OIIO::TypeDesc::FLOAT);
        const auto profile = io::CaptureProfile::fromJson(
            {{"buffers",
              {{"SceneDepth", {{"channels", {"d.Z"}}, {"scale", 100}, {"skyAbove", 1e9}}},
               {"WorldNormal", {{"channels", {"n.X", "n.Z", "n.Y"}}, {"scale", {1, 1, -1}}}},
               {"Emissive", {{"sum", {{"e.R", "e.G", "e.B"}, {"s.R", "s.G", "s.B"}}}}},
               {"GBufferAO", {{"constant", 1}}}}}},
            "/profile");
        io::CaptureFiles files(path, profile);
        std::vector<std::string> notes;
        const Image depth = files.read("SceneDepth", 1, notes);
        CHECK(depth.plane(0).at(0, 0) == 150.0f);
        CHECK(depth.plane(0).at(2, 1) == 350.0f);
        CHECK(std::isinf(depth.plane(0).at(3, 0)));
        const Image n = files.read("WorldNormal", 3, notes);
        CHECK(n.plane(0).at(1, 1) == 0.0f);
        CHECK(n.plane(1).at(1, 1) == 1.0f);   // Y ← n.Z
        CHECK(n.plane(2).at(1, 1) == -0.0f);  // Z ← −n.Y
        const Image e = files.read("Emissive", 3, notes);
        CHECK(e.plane(2).at(0, 0) == 0.75f);
        CHECK(files.read("GBufferAO", 1, notes).plane(0).at(3, 1) == 1.0f);
        CHECK(files.describe("Emissive") ==
              std::vector<std::string>{"e.R", "e.G", "e.B", "s.R", "s.G", "s.B"});
        CHECK(notes.empty());
    }

    TEST_CASE("a sum of products (Blender's light × colour passes) and a mapping's warning") {
        const std::string path = scratch("products.exr");
        writeExr(path, 2, 2, {"e.R", "e.G", "e.B", "s.R", "s.G", "s.B"},
                 [&](int, int, int c) -> float { return c < 3 ? 0.5f : 0.25f; },
                 OIIO::TypeDesc::FLOAT);
        const auto profile = io::CaptureProfile::fromJson(
            {{"buffers",
              {{"SceneColor",
                {{"sum",
                  {{{"product", {{"e.R", "e.G", "e.B"}, {"s.R", "s.G", "s.B"}}}},
                   {"e.R", "e.G", "e.B"}}},
                 {"warning", "counted twice"}}}}}},
            "/profile");
        io::CaptureFiles files(path, profile);
        std::vector<std::string> notes;
        CHECK(files.warnings().empty());
        const Image c = files.read("SceneColor", 3, notes);
        // 0.5 × 0.25 + 0.5, exact in float.
        CHECK(c.plane(1).at(1, 1) == 0.625f);
        CHECK(files.warnings() == std::set<std::string>{"SceneColor: counted twice"});
        CHECK(notes.empty());  // a warning is not an assumption (--strict does not refuse it)
        CHECK_THROWS_WITH_AS(
            io::CaptureProfile::fromJson(
                {{"buffers", {{"SceneColor", {{"sum", {{{"product", {{"e.R", "e.G", "e.B"}}}}}}}}}}},
                "/p"),
            doctest::Contains("/p/buffers/SceneColor/sum/0: a term is a channel list or {\"product\""),
            UsageError);
    }

    TEST_CASE("blender: an emitting pixel is unlit (ShadingModel 0), without an Emit pass a warning") {
        // A 3×1 Cycles layout: an emission-shader light in the middle pixel, a half-covered
        // light edge on the right (Emit averaged over the pixel), a lit wall on the left.
        const std::string path = scratch("blender_emit.exr");
        writeExr(path, 3, 1, {"ViewLayer.Emit.R", "ViewLayer.Emit.G", "ViewLayer.Emit.B"},
                 [](int x, int, int) -> float { return x == 0 ? 0.0f : x == 1 ? 10.0f : 0.01f; },
                 OIIO::TypeDesc::FLOAT);
        const auto blender = io::CaptureProfile::load("blender");
        io::CaptureFiles files(path, blender);
        std::vector<std::string> notes;
        const Image sm = files.read("ShadingModel", 1, notes);
        CHECK(sm.plane(0).at(0, 0) == 1.0f);  // Default Lit
        CHECK(sm.plane(0).at(1, 0) == 0.0f);  // Unlit: no pass lights it
        CHECK(sm.plane(0).at(2, 0) == 0.0f);
        CHECK(notes.empty());
        CHECK(files.describe("ShadingModel").front() ==
              "0 where ViewLayer.Emit.R|ViewLayer.Emit.G|ViewLayer.Emit.B > 0, else");
        // blender-direct takes its buffers from blender: the same rule.
        io::CaptureFiles direct(path, io::CaptureProfile::load("blender-direct"));
        CHECK(direct.read("ShadingModel", 1, notes).plane(0).at(1, 0) == 0.0f);

        // No Emit pass: every pixel Default Lit, said as an assumption.
        const std::string bare = scratch("blender_no_emit.exr");
        writeExr(bare, 2, 1, {"ViewLayer.Depth.Z"}, [](int, int, int) { return 1.0f; },
                 OIIO::TypeDesc::FLOAT);
        io::CaptureFiles noEmit(bare, blender);
        std::vector<std::string> bareNotes;
        CHECK(noEmit.read("ShadingModel", 1, bareNotes).plane(0).at(1, 0) == 1.0f);
        CHECK(hasNote(bareNotes, "no Emit pass"));
        // The override's shape is checked like any mapping.
        CHECK_THROWS_WITH_AS(
            io::CaptureProfile::fromJson(
                {{"buffers", {{"ShadingModel", {{"constant", 1}, {"override", {{"where", {"e.R"}}}}}}}}},
                "/p"),
            doctest::Contains("/p/buffers/ShadingModel/override: expected {\"where\""),
            UsageError);
    }

    TEST_CASE("a part that does not cover the capture's pixels is an error naming its buffer") {
        // One part per buffer, as framepass capture and Movie Render Queue write them: a
        // SceneColor part of 24×24 (or 96×96) in a 48×48 capture once read past its planes.
        const Image depth(48, 48, {"Z"});
        for (const int size : {24, 96}) {
            Image color(size, size, {"R", "G", "B"});
            const std::string path = scratch(fmt::format("parts{}.exr", size));
            io::writeExr(path,
                         {{"SceneDepth", {{"SceneDepth", &depth, false}}},
                          {"SceneColor", {{"SceneColor", &color, false}}}},
                         {});
            io::CaptureFiles files(path, io::CaptureProfile::load("canonical"));
            std::vector<std::string> notes;
            CHECK(files.read("SceneDepth", 1, notes).width() == 48);
            const std::string expected = fmt::format("buffer 'SceneColor' (channel 'SceneColor.R', part "
                                              "1) covers pixels (0,0)–({0},{0}), {1}×{1}, but "
                                              "the capture covers (0,0)–(47,47), 48×48",
                                                     size - 1, size);
            CHECK_THROWS_WITH_AS(files.read("SceneColor", 3, notes),
                                 doctest::Contains(expected.c_str()), Error);
        }
    }

    TEST_CASE("ue-mrq: half, B G R A order, a camera suffix, the camera from unreal/camera/*") {
        const std::string f1 = scratch("mrq.0001.exr"), f2 = scratch("mrq.0002.exr");
        writeMrqFrame(f1, 0.5f, {"CineCam"}, kMrqCamera);
        writeMrqFrame(f2, 0.125f, {"CineCam"}, kMrqCamera);
        const auto profile = io::CaptureProfile::load("ue-mrq");

        io::CaptureSource::Options o;
        o.path = f2;
        o.previousPath = f1;
        o.frame = 2;
        io::CaptureSource source(o, profile);
        const FrameInfo info = source.frameInfo();
        REQUIRE(info.hasCamera);
        const CameraView& c = info.camera.current;
        CHECK(length(c.position - Vec3d{100, 200, 50}) < 1e-12);
        const double p = -10 * kPi / 180, y = 30 * kPi / 180;
        CHECK(length(c.forward - Vec3d{std::cos(p) * std::cos(y), std::cos(p) * std::sin(y),
                                       std::sin(p)}) < 1e-12);
        CHECK(length(c.right - Vec3d{-std::sin(y), std::cos(y), 0}) < 1e-12);  // roll 0
        CHECK(c.fx == doctest::Approx(1.0));  // horizontal FOV 90°
        CHECK(c.fy == doctest::Approx(double(kW) / kH));
        CHECK(info.camera.sceneUnitsPerMeter == 100.0);
        REQUIRE(info.camera.previous);
        CHECK(info.camera.previous->position.x == 90.0);
        CHECK(hasNote(source.notes(), "near plane not in the header: assumed 10 cm"));

        const Image depth = source.loadBuffer("SceneDepth", 1).image();
        CHECK(std::isinf(depth.plane(0).at(0, 0)));
        CHECK(depth.plane(0).at(3, 2) == 132.0f);
        const Image n = source.loadBuffer("WorldNormal", 3).image();
        CHECK(n.plane(2).at(4, 4) == 1.0f);
        const Image base = source.loadBuffer("BaseColor", 3).image();
        CHECK(base.plane(0).at(1, 1) == 0.25f);  // R, though the file lists B first
        CHECK(base.plane(2).at(1, 1) == 0.75f);
        CHECK(source.loadBuffer("SceneColor", 3).image().plane(1).at(5, 5) == 0.25f);
        // Frame N−1's FinalImage is this frame's previous colour.
        const Image prev = source.loadBuffer("PrevSceneColor", 3).image();
        CHECK(prev.plane(0).at(2, 3) == 0.5f);
        CHECK(prev.plane(2).at(2, 3) == 1.5f);
        // No FP_Roughness layer: the profile's stand-in, said as a warning.
        CHECK(source.loadBuffer("Roughness", 1).image().plane(0).at(0, 0) == 0.5f);
        CHECK(hasNote(source.notes(), "no FP_Roughness layer: roughness 0.5 everywhere"));
        CHECK(hasNote(source.notes(), "half float"));

        // The first frame of a sequence has no frame N−1: no history, said once.
        o.path = f1;
        o.previousPath = scratch("mrq.0000.exr");
        io::CaptureSource first(o, profile);
        const Image none = first.loadBuffer("PrevSceneDepth", 1).image();
        CHECK(std::isinf(none.plane(0).at(4, 4)));
        CHECK(first.loadBuffer("PrevSceneColor", 3).image().plane(0).at(4, 4) == 0.0f);
        CHECK(hasNote(first.notes(), "no history, as after a camera cut"));

        // --strict: an assumed value is an error.
        o.strict = true;
        io::CaptureSource strict(o, profile);
        CHECK_THROWS_WITH_AS(strict.frameInfo(), doctest::Contains("--strict"), UsageError);
    }

    TEST_CASE("ue-mrq: two cameras in one file need a choice; Movie Render Graph's spelling") {
        const std::string path = scratch("mrq_two.exr");
        std::map<std::string, std::string> graph;
        for (const auto& [k, v] : kMrqCamera) {
            std::string key = k;
            key.replace(0, std::string("unreal/camera/").size(),
                        "unreal/layerData/beauty/camera/");
            if (key.ends_with("FinalImage/fov")) key = "unreal/layerData/beauty/camera/fov";
            graph[key] = v;
        }
        writeMrqFrame(path, 0.5f, {"A", "B"}, graph);
        CHECK_THROWS_WITH_AS(io::CaptureFiles(path, io::CaptureProfile::load("ue-mrq")),
                             doctest::Contains("layers of several cameras ([A, B])"), UsageError);
        const auto chosen = io::CaptureProfile::fromJson({{"base", "ue-mrq"}, {"camera", "B"}}, "/p");
        io::CaptureFiles files(path, chosen);
        CHECK(files.describe("BaseColor").front() == "FinalImageFP_BaseColor_B.R");
        std::vector<std::string> assumed;
        const auto cam = io::readCameraAttributes(files.primary().header(), files.extent(), assumed);
        REQUIRE(cam);
        CHECK(cam->current.position.y == 200.0);
        CHECK(cam->current.fx == doctest::Approx(1.0));

        // Without fov, the lens gives it: 36 mm sensor, 18 mm lens = 90° horizontal.
        Imf::Header lens(kW, kH);
        for (const auto& [k, v] : kMrqCamera)
            if (!k.ends_with("/fov")) lens.insert(k, Imf::StringAttribute(v));
        lens.insert("unreal/camera/FinalImage/focalLength", Imf::StringAttribute("18"));
        const auto fromLens = io::readCameraAttributes(lens, {kW, kH}, assumed);
        REQUIRE(fromLens);
        CHECK(fromLens->current.fx == doctest::Approx(1.0));
        lens.insert("unreal/camera/curRot/yaw", Imf::StringAttribute("thirty"));
        CHECK_THROWS_WITH_AS(io::readCameraAttributes(lens, {kW, kH}, assumed),
                             doctest::Contains("'unreal/camera/curRot/yaw' is 'thirty', not a number"),
                             UsageError);
    }

    TEST_CASE("ue-bufvis: one file per buffer, packed normals found, an Unreal-style sidecar") {
        const std::string base = scratch("HighresScreenshot00000");
        const auto rgba = std::vector<std::string>{"R", "G", "B", "A"};
        writeExr(base + "_SceneDepthWorldUnits.exr", kW, kH, rgba,
                 [](int x, int, int c) { return c == 3 ? 1.0f : 500.0f + x; },
                 OIIO::TypeDesc::FLOAT);
        // Packed normals n·0.5+0.5 of (0.6, 0, 0.8).
        writeExr(base + "_WorldNormal.exr", kW, kH, rgba,
                 [](int, int, int c) { return c == 0 ? 0.8f : c == 1 ? 0.5f : c == 2 ? 0.9f : 1.0f; },
                 OIIO::TypeDesc::HALF);
        writeExr(base + "_BaseColor.exr", kW, kH, rgba,
                 [](int, int, int c) { return 0.5f; }, OIIO::TypeDesc::HALF);
        std::ofstream(base + ".camera.json")
            << R"({"position": [0, 0, 150], "rotation": {"pitch": 0, "yaw": 90, "roll": 0},
                  "fovXDegrees": 90, "sceneUnitsPerMeter": 100})";

        // Any one of the files names the capture.
        io::CaptureSource::Options o;
        o.path = base + "_BaseColor.exr";
        io::CaptureSource source(o, io::CaptureProfile::load("ue-bufvis"));
        CHECK(source.files().capturePath() == base);
        const FrameInfo info = source.frameInfo();
        REQUIRE(info.hasCamera);
        CHECK(length(info.camera.current.forward - Vec3d{0, 1, 0}) < 1e-12);  // yaw 90°
        CHECK(length(info.camera.current.right - Vec3d{-1, 0, 0}) < 1e-12);
        CHECK(info.camera.current.fx == doctest::Approx(1.0));
        CHECK(info.camera.current.nearPlane == doctest::Approx(10.0));
        CHECK(hasNote(source.notes(), "no 'near': assumed 10 cm (10 scene units)"));
        const Image n = source.loadBuffer("WorldNormal", 3).image();
        CHECK(n.plane(0).at(2, 2) == doctest::Approx(0.6f).epsilon(1e-3));  // half: 11 bits
        CHECK(n.plane(2).at(2, 2) == doctest::Approx(0.8f).epsilon(1e-3));
        CHECK(hasNote(source.notes(), "normals read as packed"));
        CHECK(source.loadBuffer("SceneDepth", 1).image().plane(0).at(3, 0) == 503.0f);
        CHECK(source.loadBuffer("ShadingModel", 1).image().plane(0).at(0, 0) == 1.0f);
        const auto avail = source.files().availableBuffers();
        CHECK(avail.count("BaseColor"));
        CHECK(!avail.count("SceneColor"));  // no _SceneColor / _PreTonemapHDRColor file
        CHECK(!avail.count("PrevSceneColor"));
        CHECK_THROWS_WITH_AS(io::CaptureFiles(scratch("Nothing00000"),
                                              io::CaptureProfile::load("ue-bufvis")),
                             doctest::Contains("no file of this capture exists"), Error);
    }
}
