// ssr (algorithms §5) against hand-worked values: the quality table and roughness fade, the shared
// HZB march's interpolated hit, a mirror floor reflecting a glowing wall × EnvBRDF, rough pixels
// skipped and counted, thread counts.
#include "screenspace/HzbMarch.h"
#include "shading/EnvBRDF.h"
#include "passes/ssr/SSRPass.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace fp {

namespace {

// floorAndWall() with the floor a black mirror-like dielectric of `roughness` that still glows
// kGlow: every screen pixel's colour is kGlow, so a hit gathers exactly kGlow.
Scene glowingRoom(float roughness) {
    Scene s = test::floorAndWall();
    Material floor = test::lambert(0.0f, test::kGlow);
    floor.specular = 0.5f;
    floor.roughness = roughness;
    s.materials.push_back(floor);
    s.meshes[0].material = 1;
    return s;
}

struct Run {
    Image reflection, specular;
    std::map<std::string, uint64_t> work;
};

Run runSsr(test::MemorySource& src, nlohmann::json params = nlohmann::json::object()) {
    test::MemorySink sink;
    const Plan plan = test::planFor(
        {test::node("hzb"), test::node("ssr", params, {{"furthestHzb", "hzb.furthest"}}),
         test::node("reflection_environment", {}, {{"reflection", "ssr.reflection"}})},
        {"ssr.reflection", "reflection_environment.specular"});
    const FrameReport report = executePlan(plan, src, sink);
    std::map<std::string, uint64_t> work;
    for (const auto& p : report.passes)
        if (p.name == "ssr") work = p.work;
    return {sink.layers.at("ssr.reflection").image(), sink.layers.at("reflection_environment.specular").image(),
            work};
}

bool isFloor(const test::MemorySource& src, int x, int y) {
    return src.buffers.at("WorldNormal").plane(1).at(x, y) > 0.99f;
}

}  // namespace

TEST_CASE("ssr: the quality table and the roughness fade") {
    // Unreal's defaults (cvar 3, post-process 50) run Medium: 16 steps, one mirror ray.
    const SSRQuality medium = SSRPass::effectiveQuality(3, 50, 100.0f);
    CHECK(medium.level == 2);
    CHECK(medium.steps == 16);
    CHECK(medium.rays == 1);
    CHECK_FALSE(medium.glossy);
    const SSRQuality epic = SSRPass::effectiveQuality(4, 100, 100.0f);
    CHECK((epic.level == 4 && epic.steps == 12 && epic.rays == 12 && epic.glossy));
    const SSRQuality high = SSRPass::effectiveQuality(4, 70, 100.0f);
    CHECK((high.level == 3 && high.steps == 8 && high.rays == 4 && high.glossy));
    CHECK(SSRPass::effectiveQuality(1, 100, 100.0f).level == 1);
    CHECK(SSRPass::effectiveQuality(0, 100, 100.0f).level == 0);
    CHECK(SSRPass::effectiveQuality(4, 100, 0.5f).level == 0);
    // §5.2 with max roughness 0.6: High/Epic fade 1 up to 0.3 and 0 at 0.6; Low/Medium twice as fast.
    CHECK(SSRPass::roughnessFade(0.3f, 0.6f, 3) == doctest::Approx(1.0f));
    CHECK(SSRPass::roughnessFade(0.45f, 0.6f, 4) == doctest::Approx(0.5f));
    CHECK(SSRPass::roughnessFade(0.6f, 0.6f, 3) == doctest::Approx(0.0f).epsilon(1e-6));
    CHECK(SSRPass::roughnessFade(0.15f, 0.6f, 2) == doctest::Approx(1.0f));
    CHECK(SSRPass::roughnessFade(0.3f, 0.6f, 1) == doctest::Approx(0.0f).epsilon(1e-6));
}

TEST_CASE("marchHzb: SSR's hit lies where the ray crosses the surface") {
    // A screen-wide surface at device Z 0.5 (one HZB mip), a ray from Z 0.9 receding by 0.07 a
    // sample: it crosses at t* = 0.4/0.07 = 5.714, so sample 6 is the first behind the surface
    // (by 0.02, within 2·tolerance = 0.2), and the depths are linear along the ray, so the
    // interpolation between samples 5 and 6 lands on t* itself (float rounding).
    Plane cells(16, 16, 0.5f);
    HzbView hzb;
    hzb.mips[0] = viewOf(cells);
    hzb.mipCount = 1;
    RaySteps r;
    r.origin = {2.0f, 3.0f, 0.9f};
    r.step = {0.5f, 0.25f, -0.07f};
    r.tolerance = 0.1f;
    float level = 0, time = -1;
    unsigned samples = 0;
    CHECK(marchHzb(hzb, r, 8, 1.0f, level, samples, &time) == 6);
    CHECK(time == doctest::Approx(0.4 / 0.07).epsilon(1e-5));
    CHECK(samples == 8);  // two batches of 4: the hit is in the second
    // SSGI's call, without the interpolation, finds the same sample.
    CHECK(marchHzb(hzb, r, 8, 1.0f, level, samples) == 6);
    // A hit on the first sample interpolates from the origin's difference taken as 0: time 0.
    r.origin.z = 0.55f;
    CHECK(marchHzb(hzb, r, 8, 1.0f, level, samples, &time) == 1);
    CHECK(time == 0.0f);
}

TEST_CASE("ssr: a mirror floor reflects the glowing wall's radiance × EnvBRDF") {
    const Scene scene = glowingRoom(0.0f);
    const FrameCamera cam = test::wallCamera(48);
    test::MemorySource src = test::captureToMemory(scene, cam);
    const Run run = runSsr(src);
    const EnvBRDFLut& lut = EnvBRDFLut::instance();
    int full = 0, partial = 0, floorPixels = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            if (!isFloor(src, x, y)) continue;
            ++floorPixels;
            const float a = run.reflection.plane(3).at(x, y);
            // Every hit reads kGlow; the vignette scales colour and coverage alike (fade 1).
            CHECK(run.reflection.plane(0).at(x, y) == doctest::Approx(test::kGlow * a).epsilon(1e-5));
            if (a < 1.0f) {
                partial += a > 0.0f;
                continue;
            }
            ++full;
            // reflection_environment: SSR covers everything, the sky gets no weight, and the
            // result is kGlow × EnvBRDF(F0 = 0.04, roughness 0, NoV).
            const double depth = src.buffers.at("SceneDepth").plane(0).at(x, y);
            const Vec3d p = cam.current.translatedFromPixel(x, y, depth);
            const float NoV = saturate(float(-p.y / length(p)));
            const EnvBRDFTerms t = lut.lookup(NoV, 0.0f);
            CHECK(run.specular.plane(0).at(x, y) ==
                  doctest::Approx(test::kGlow * (0.04f * t.a + t.b)).epsilon(1e-4));
        }
    CAPTURE(floorPixels);
    CHECK(full > floorPixels / 3);
    CHECK(partial > 0);  // rays that end near the screen's edge fade out
    CHECK(run.work.at("pixels") == uint64_t(floorPixels));  // the wall (roughness 1) is skipped
}

TEST_CASE("ssr: pixels past the roughness cutoff are untouched and counted") {
    const FrameCamera cam = test::wallCamera(32);
    for (float roughness : {0.35f, 0.7f}) {
        const Scene scene = glowingRoom(roughness);
        test::MemorySource src = test::captureToMemory(scene, cam);
        uint64_t floorPixels = 0, lit = 0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                floorPixels += isFloor(src, x, y);
                lit += !std::isinf(src.buffers.at("SceneDepth").plane(0).at(x, y));
            }
        CAPTURE(roughness);
        // Medium (the defaults) fades out at 0.3: the floor and the wall (roughness 1) are all
        // skipped, their reflection 0.
        Run medium = runSsr(src);
        CHECK(medium.work.at("roughPixels") == lit);
        CHECK(medium.work["pixels"] == 0);
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) CHECK(medium.reflection.plane(3).at(x, y) == 0.0f);
        // Epic fades out at 0.6: a floor of 0.35 is traced, 12 GGX rays a pixel; one of 0.7 not.
        Run epic = runSsr(src, {{"quality", 4}, {"postProcessQuality", 100}});
        const uint64_t traced = roughness < 0.6f ? floorPixels : 0;
        CHECK(epic.work["pixels"] == traced);
        CHECK(epic.work.at("roughPixels") == lit - traced);
        CHECK(epic.work["rays"] == traced * 12);
    }
}

TEST_CASE("ssr: quality 0 traces nothing, and every output asked for exists, all 0") {
    const FrameCamera cam = test::wallCamera(16);
    const Scene scene = glowingRoom(0.1f);
    test::MemorySource src = test::captureToMemory(scene, cam);
    test::MemorySink sink;
    const Plan plan = test::planFor(
        {test::node("hzb"), test::node("ssr", {{"quality", 0}}, {{"furthestHzb", "hzb.furthest"}})},
        {"ssr.reflection", "ssr.hitMask", "ssr.hitDistance"});
    const FrameReport report = executePlan(plan, src, sink);
    CHECK(report.passes.back().work.at("skippedPixels") == 16 * 16);
    for (const char* name : {"ssr.reflection", "ssr.hitMask", "ssr.hitDistance"}) {
        CAPTURE(name);
        REQUIRE(sink.layers.count(name));
        const Image& image = sink.layers.at(name).image();
        for (int c = 0; c < image.channelCount(); ++c)
            for (int y = 0; y < 16; ++y)
                for (int x = 0; x < 16; ++x) CHECK(image.plane(c).at(x, y) == 0.0f);
    }
}

TEST_CASE("ssr: 1 and 2 threads give the same bits") {
    const Scene scene = glowingRoom(0.2f);
    const FrameCamera cam = test::wallCamera(40);
    test::MemorySource src = test::captureToMemory(scene, cam);
    const Run two = runSsr(src, {{"quality", 4}, {"postProcessQuality", 100}});
    Run one;
    {
        tbb::global_control only(tbb::global_control::max_allowed_parallelism, 1);
        one = runSsr(src, {{"quality", 4}, {"postProcessQuality", 100}});
    }
    for (int c = 0; c < 4; ++c) CHECK(test::sameBits(one.reflection.plane(c), two.reflection.plane(c)));
    CHECK(two.work.at("hzbSamples") > 0);
}

}  // namespace fp

namespace fp {

TEST_CASE("ssr: r.SSR.Temporal smooths across frames within this frame's neighbourhood") {
    // A still camera on the glossy glowing room, Epic's 12 GGX rays jittered by the frame index:
    // frame 1 has no history (the raw reflection), later frames move 1/8 of the way from the
    // clamped history, so each pixel stays within its 3×3 neighbourhood of the raw frame and the
    // frame-to-frame change shrinks.
    const Scene scene = glowingRoom(0.25f);
    const FrameCamera cam = test::wallCamera(32);
    const nlohmann::json epic = {{"quality", 4}, {"postProcessQuality", 100}};
    nlohmann::json smoothed = epic;
    smoothed["temporal"] = true;
    const Plan raw = test::planFor({test::node("hzb"), test::node("ssr", epic, {{"furthestHzb", "hzb.furthest"}})},
                                   {"ssr.reflection"});
    const Plan temporal = test::planFor(
        {test::node("hzb"), test::node("ssr", smoothed, {{"furthestHzb", "hzb.furthest"}})}, {"ssr.reflection"});
    HistoryStore history;
    std::vector<Image> raws, outs;
    for (int64_t frame = 1; frame <= 4; ++frame) {
        test::MemorySource src = test::captureToMemory(scene, cam, frame);
        src.info.firstInSequence = frame == 1;
        test::MemorySink a, b;
        executePlan(raw, src, a);
        const FrameReport report = executePlan(temporal, src, b, {}, &history);
        raws.push_back(a.layers.at("ssr.reflection").image());
        outs.push_back(b.layers.at("ssr.reflection").image());
        // No sky on screen and a still camera: from frame 2 every pixel has a history.
        std::map<std::string, uint64_t> work = report.passes.back().work;
        CHECK(work["historyPixels"] == (frame == 1 ? 0u : 32u * 32u));
    }
    for (int c = 0; c < 4; ++c) CHECK(test::sameBits(outs[0].plane(c), raws[0].plane(c)));
    double rawChange = 0, smoothChange = 0;
    int changed = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            float lo = 1e9f, hi = -1e9f;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const float v = raws[3].plane(0).clampedAt(x + dx, y + dy);
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            const float v = outs[3].plane(0).at(x, y);
            CHECK(v >= lo - 1e-6f);
            CHECK(v <= hi + 1e-6f);
            changed += v != raws[3].plane(0).at(x, y);
            rawChange += std::abs(raws[3].plane(0).at(x, y) - raws[2].plane(0).at(x, y));
            smoothChange += std::abs(outs[3].plane(0).at(x, y) - outs[2].plane(0).at(x, y));
        }
    CHECK(changed > 0);
    CHECK(smoothChange < 0.5 * rawChange);
}

}  // namespace fp

namespace fp {

TEST_CASE("error_measure: maxRoughness measures only the pixels under SSR's cutoff") {
    // The glowing room: a floor of roughness 0.2, a wall of 1. Measured against black, every
    // pixel is off by kGlow; with maxRoughness 0.6 only the floor's pixels count.
    const Scene scene = glowingRoom(0.2f);
    const FrameCamera cam = test::wallCamera(24);
    test::MemorySource src = test::captureToMemory(scene, cam);
    uint64_t floorPixels = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) floorPixels += isFloor(src, x, y);
    REQUIRE(floorPixels > 0);
    REQUIRE(floorPixels < 24u * 24u);
    for (float maxRoughness : {0.0f, 0.6f}) {
        test::MemorySink sink;
        const Plan plan = test::planFor(
            {test::node("error_measure", {{"maxRoughness", maxRoughness}},
                        {{"source", "capture:SceneColor"}, {"reference", "capture:BaseColor"}})},
            {"error_measure.absError"});
        const FrameReport report = executePlan(plan, src, sink);
        CAPTURE(maxRoughness);
        CHECK(report.passes.back().work.at("pixels") == (maxRoughness > 0 ? floorPixels : 24u * 24u));
        CHECK(report.passes.back().metrics.at("mae") == doctest::Approx(test::kGlow).epsilon(1e-5));
    }
}

}  // namespace fp
