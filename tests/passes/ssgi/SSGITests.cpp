// ssgi (and the composite that reads it), run through the real planner and executor on
// in-memory captures of small analytic scenes.
#include "io/scene/SceneLoader.h"
#include "screenspace/Reprojection.h"
#include "framework/Executor.h"
#include "foundation/Sampling.h"
#include "foundation/UnrealRandom.h"
#include "passes/prev_color_reduction/PrevColorReductionPass.h"
#include "screenspace/Lanes.h"
#include "passes/ssgi/SSGILanes.h"
#include "passes/ssgi/SSGIPass.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace fp;

namespace {

using test::floorAndWall;
using test::kGlow;
using test::wallCamera;

// Form factor from floor point p to the on-screen wall; `vignetted` also weighs each cell by the
// vignette at its screen position (what the reduced colour holds there).
double onScreenWallFormFactor(const Vec3d& p, const CameraView& cam, bool vignetted) {
    return test::onScreenWallFormFactor(p, cam, [&](double sx, double sy) {
        return vignetted ? double(vignette(float(sx), float(sy))) : 1.0;
    });
}

std::vector<NodeDesc> ssgiChain(nlohmann::json ssgiParams = nlohmann::json::object()) {
    return {test::node("hzb"),
            test::node("prev_color_reduction", {}, {{"furthestHzb", "hzb.furthest"}}),
            test::node("ssgi", ssgiParams,
                       {{"furthestHzb", "hzb.furthest"},
                        {"reducedColor", "prev_color_reduction.color"}})};
}

}  // namespace

TEST_SUITE("ssgi") {

TEST_CASE("quality levels trace 4/8/16/32 rays of 8/8/8/12 steps") {
    const int rays[] = {4, 8, 16, 32}, steps[] = {8, 8, 8, 12};
    for (int q = 1; q <= 4; ++q) {
        CHECK(SSGIPass::qualityTable(q).rays == rays[q - 1]);
        CHECK(SSGIPass::qualityTable(q).steps == steps[q - 1]);
        // Under an empty sky no ray hits (except false self-hits in the outermost pixels, see the
        // next case), so every interior ray takes all its steps.
        Scene s = test::floorScene();
        FrameCamera cam;
        cam.current = CameraView::lookAt({0, 40, -10}, {0, 0, 10}, {0, 1, 0}, 60.0, 24, 16, 1.0);
        cam.previous = cam.current;
        auto src = test::captureToMemory(s, cam);
        test::MemorySink sink;
        const FrameReport r = executePlan(
            test::planFor(ssgiChain({{"quality", q}}), {"ssgi.diffuse"}), src, sink);
        const auto& work = r.passes.back().work;
        CHECK(work.at("rays") == uint64_t(rays[q - 1]) * work.at("pixels"));
        const uint64_t all = uint64_t(steps[q - 1]) * work.at("rays");
        const uint64_t border = uint64_t(steps[q - 1]) * rays[q - 1] * (2 * 24 + 2 * 14);
        CHECK(work.at("hzbSamples") <= all);
        CHECK(work.at("hzbSamples") >= all - border);
    }
}

TEST_CASE("rays replaces the quality's ray count and keeps its steps") {
    // Quality 1 and 3 differ only in their ray count (4 and 16, both 8 steps), so quality 1 with
    // rays = 16 is quality 3 bit for bit; beyond 32 rays (quality 4's) the lanes still give the
    // scalar reference's bits, with a count no vector width divides.
    Scene room = floorAndWall();
    room.meshes.push_back(test::sphere({2, 3, 10}, 3.0, 16));
    auto src = test::captureToMemory(room, wallCamera(21), 3);
    auto trace = [&](nlohmann::json params) {
        return test::runChain(src, ssgiChain(params), {"ssgi.diffuse", "ssgi.hitMask"});
    };
    const auto q3 = trace({{"quality", 3}});
    const auto q1With16 = trace({{"quality", 1}, {"rays", 16}});
    for (const char* o : {"ssgi.diffuse", "ssgi.hitMask"})
        for (int c = 0; c < q3.at(o).image().channelCount(); ++c)
            CHECK(test::sameBits(q3.at(o).image().plane(c), q1With16.at(o).image().plane(c)));
    const auto lanes = trace({{"quality", 4}, {"rays", 203}});
    const auto scalar = trace({{"quality", 4}, {"rays", 203}, {"lanes", false}});
    for (const char* o : {"ssgi.diffuse", "ssgi.hitMask"})
        for (int c = 0; c < lanes.at(o).image().channelCount(); ++c)
            CHECK(test::sameBits(lanes.at(o).image().plane(c), scalar.at(o).image().plane(c)));
    CHECK_THROWS(trace({{"quality", 4}, {"rays", SSGIPass::kMaxRays + 1}}));
}

TEST_CASE("SIMD lanes give the scalar reference's bits") {
    // The CPU traces a pixel's rays a vector at a time (SSGILanes.cpp) doing the scalar
    // ssgiPixel's IEEE operations lane by lane, so every output must match it bit for bit: on a
    // closed room (every ray can hit) and on a floor under an open sky (rays leave the screen and
    // hit the sky), a sphere on the floor for occlusion, every quality (4 to 32 rays, so whole and
    // part-filled vectors), full and half resolution, two frame indices, a size that is no
    // multiple of any vector width; and every instruction set the build has lanes for that this
    // CPU runs (SSE4, AVX2, AVX-512…).
    Scene room = floorAndWall();
    room.meshes.push_back(test::sphere({2, 3, 10}, 3.0, 16));
    Scene open = test::floorScene();
    open.meshes.push_back(test::sphere({0, 3, 10}, 3.0, 16));
    FrameCamera openCam;
    openCam.current = CameraView::lookAt({0, 8, -10}, {0, 2, 20}, {0, 1, 0}, 60.0, 37, 29, 1.0);
    openCam.previous = openCam.current;
    FrameCamera roomCam = wallCamera(37);
    // The Cornell box: coloured walls under its ceiling light, so each hit's colour depends on
    // which reduced mip it reads.
    const io::SceneFile cornell =
        io::loadScene(std::string(FP_SOURCE_DIR) + "/examples/cornell/scene.json");
    const FrameCamera cornellCam = cornell.cameraForFrame(1, {41, 31});
    // With the debug hit distance read, hits are shaded one at a time; without it, in lanes.
    const std::vector<std::string> withDistance = {"ssgi.diffuse", "ssgi.ao", "ssgi.hitMask",
                                                   "ssgi.hitDistance"};
    const std::vector<std::string> withoutDistance = {"ssgi.diffuse", "ssgi.ao", "ssgi.hitMask"};
    const std::vector<int64_t> targets = laneTargetsHere();
    REQUIRE(!targets.empty());
    int compared = 0;
    using Shot = std::pair<const Scene*, const FrameCamera*>;
    for (int64_t target : targets)
    for (const auto& [scene, cam] : {Shot{&room, &roomCam}, Shot{&open, &openCam},
                                     Shot{&cornell.scene, &cornellCam}})
        for (int64_t frame : {1, 6}) {
            auto src = test::captureToMemory(*scene, *cam, frame);
            for (int q = 1; q <= 4; ++q)
                for (bool halfRes : {false, true})
                for (const auto* outs : {&withDistance, &withoutDistance}) {
                    const std::vector<std::string>& outputs = *outs;
                    const nlohmann::json params = {{"quality", q}, {"halfRes", halfRes}};
                    nlohmann::json scalarParams = params;
                    scalarParams["lanes"] = false;
                    test::MemorySink lanes, scalar;
                    useOnlyLaneTarget(target);
                    const std::string laneName = ssgi::laneTarget().name;
                    INFO("lanes: ", laneName);
                    const FrameReport a =
                        executePlan(test::planFor(ssgiChain(params), outputs), src, lanes);
                    useOnlyLaneTarget(0);
                    const FrameReport b =
                        executePlan(test::planFor(ssgiChain(scalarParams), outputs), src, scalar);
                    CHECK(a.passes.back().work == b.passes.back().work);
                    CHECK(a.passes.back().work.at("hzbSamples") > 0);
                    for (const auto& o : outputs) {
                        const Image& img = lanes.layers.at(o).image();
                        for (int c = 0; c < img.channelCount(); ++c)
                            CHECK_MESSAGE(test::sameBits(img.plane(c),
                                                         scalar.layers.at(o).image().plane(c)),
                                          o, " quality ", q, " halfRes ", halfRes);
                    }
                    // The comparison means something: some rays hit, some miss.
                    const Plane& hitMask = lanes.layers.at("ssgi.hitMask").image().plane(0);
                    float lo = 1, hi = 0;
                    for (int y = 0; y < hitMask.height(); ++y)
                        for (int x = 0; x < hitMask.width(); ++x) {
                            lo = std::min(lo, hitMask.at(x, y));
                            hi = std::max(hi, hitMask.at(x, y));
                        }
                    CHECK(hi > 0.0f);
                    CHECK(lo < 1.0f);
                    ++compared;
                }
        }
    CHECK(compared == 96 * int(targets.size()));
}

TEST_CASE("ray directions are cosine-distributed around the normal") {
    // Moments of cosθ over many pixels' ray sets: E[cosθ] = 2/3, E[cos²θ] = 1/2, and the tangent
    // components average 0. Standard deviations are √(1/2 − 4/9) = 0.236 for cosθ and
    // √(1/3 − 1/4) = 0.289 for cos²θ; with n samples, 5σ/√n bounds the mean even without the
    // stratification Hammersley adds.
    for (const Vec3f n : {Vec3f{0, 0, 1}, normalize(Vec3f{0.3f, -0.5f, -0.8f})}) {
        Vec3f t, b;
        orthonormalBasis(n, t, b);
        double m1 = 0, m2 = 0, mt = 0, mb = 0;
        int count = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                for (int r = 0; r < 8; ++r) {
                    const Vec3f d = SSGIPass::rayDirection(n, x, y, 3, r, 8);
                    CHECK(std::abs(dot(d, d) - 1.0f) < 1e-5f);
                    const double c = dot(d, n);
                    REQUIRE(c >= 0.0);
                    m1 += c;
                    m2 += c * c;
                    mt += dot(d, t);
                    mb += dot(d, b);
                    ++count;
                }
        const double k = 5.0 / std::sqrt(double(count));
        CHECK(std::abs(m1 / count - 2.0 / 3.0) < 0.236 * k);
        CHECK(std::abs(m2 / count - 0.5) < 0.289 * k);
        CHECK(std::abs(mt / count) < 0.5 * k);
        CHECK(std::abs(mb / count) < 0.5 * k);
    }
}

TEST_CASE("Unreal's random primitives: PCG hash, Hammersley and interleaved gradient noise") {
    // Hammersley16 with a zero seed is the plain radical-inverse set.
    float e1, e2;
    ue::hammersley16(1, 4, 0, 0, e1, e2);
    CHECK(e1 == 0.25f);
    CHECK(e2 == 0.5f);
    ue::hammersley16(3, 4, 0, 0, e1, e2);
    CHECK(e2 == 0.75f);
    // Different pixels and frames give different 16-bit seeds.
    const ue::Rand3 a = ue::rand3DPCG16(0, 0, 0), b = ue::rand3DPCG16(1, 0, 0), c = ue::rand3DPCG16(0, 0, 1);
    CHECK(a.x < 65536u);
    CHECK((a.x != b.x || a.y != b.y));
    CHECK((a.x != c.x || a.y != c.y));
    for (float x : {0.5f, 7.5f, 100.5f}) {
        const float v = ue::interleavedGradientNoise(x, 3.5f, 5);
        CHECK(v >= 0.0f);
        CHECK(v < 1.0f);
    }
}

TEST_CASE("an unoccluded plane under an empty sky gathers (almost) nothing") {
    Scene s = test::floorScene();
    Light l;
    l.position = {0, 40, 0};
    l.intensity = 5000.0f;
    s.lights.push_back(l);  // the floor is brightly lit: only an occluder could gather it
    FrameCamera cam;
    // Looking down, so the plane fills the view.
    cam.current = CameraView::lookAt({0, 40, -10}, {0, 0, 10}, {0, 1, 0}, 60.0, 64, 48, 1.0);
    cam.previous = cam.current;
    auto src = test::captureToMemory(s, cam);
    const auto out = test::runChain(src, ssgiChain(), {"ssgi.diffuse", "ssgi.ao"});
    const Image& d = out.at("ssgi.diffuse").image();
    const Plane& ao = out.at("ssgi.ao").image().plane(0);
    const Plane& lit = src.buffers.at("SceneColor").plane(0);
    // Unreal's march is not exactly self-hit free: the HZB holds depths at pixel centres, so a
    // grazing ray's first sample, within half a pixel of the centre of the farthest row of its
    // HZB texel (or past the screen edge, where reads clamp), finds that row in front of it and
    // stops. On this plane that costs a few rays, mostly in the first row of every 4-pixel HZB
    // block and at the borders (measured mean AO 0.9923, gathered 0.41 % of the plane's radiance). The
    // bounds below allow twice that; a march that tested against the wrong mip or sign would hit
    // on every pixel.
    double aoSum = 0, gathered = 0, radiance = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            aoSum += ao.at(x, y);
            gathered += d.plane(0).at(x, y);
            radiance += lit.at(x, y);
        }
    CHECK(aoSum / (48 * 64) >= 0.985);
    CHECK(gathered / radiance <= 0.0083);
}

TEST_CASE("a floor beside a glowing wall gathers the form-factor irradiance") {
    const int size = 96;
    Scene s = floorAndWall();
    const FrameCamera cam = wallCamera(size);
    auto src = test::captureToMemory(s, cam);
    const auto out = test::runChain(src, ssgiChain({{"quality", 4}}), {"ssgi.diffuse", "ssgi.ao"});
    const Plane& diffuse = out.at("ssgi.diffuse").image().plane(0);
    const Plane& ao = out.at("ssgi.ao").image().plane(0);
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    const int rays = SSGIPass::qualityTable(4).rays;
    double sqErr = 0, sqNoise = 0, colourErr = 0, colourRef = 0;
    int n = 0;
    for (int y = 0; y < size; y += 3)
        for (int x = 0; x < size; x += 3) {
            const Vec3d p = cam.current.worldFromPixel(x, y, depth.at(x, y));
            if (std::abs(p.y) > 1e-3 || p.z > 28.0) continue;  // floor pixels only
            const double F = onScreenWallFormFactor(p, cam.current, false);
            if (F < 0.05) continue;
            const double h = 1.0 - ao.at(x, y);
            sqErr += (h - F) * (h - F);
            sqNoise += F * (1 - F) / rays;  // variance of the hit fraction of `rays` random rays
            // Hits of radiance L (vignetted) and misses of 0, Karis-weighted and unweighted after
            // the mean: L·Fv/(1 + l(1 − Fv)) with l = luma(L) = L for grey.
            const double Fv = onScreenWallFormFactor(p, cam.current, true);
            const double expected = kGlow * Fv / (1.0 + kGlow * (1.0 - Fv));
            colourErr += diffuse.at(x, y) - expected;
            colourRef += expected;
            ++n;
        }
    REQUIRE(n > 100);
    const double rmsErr = std::sqrt(sqErr / n), rmsNoise = std::sqrt(sqNoise / n);
    MESSAGE("hit fraction RMS error " << rmsErr << ", independent-ray noise " << rmsNoise
            << ", colour bias " << colourErr / colourRef << " over " << n << " pixels");
    // The geometry: hit fractions agree with the on-screen form factor to within the noise of 32
    // independent rays (Hammersley stratification makes the real noise smaller).
    CHECK(rmsErr < rmsNoise);
    // The colour: hits read 8–32-pixel texels of the reduced chain, where the vignette's concave
    // ramp is box-averaged, i.e. darker than its point value. The deficit shrinks as texels get
    // small against the screen (measured −13 % at 64², −12 % at 96², −9 % at 192²); 15 % bounds it at this size while a wrong gather (a mip off by one
    // level, a Karis weight not undone) would be off by far more.
    CHECK(colourErr / colourRef < 0.0);
    CHECK(colourErr / colourRef > -0.15);
}

TEST_CASE("sky and unlit pixels are skipped by SSGI and left untouched by the composite") {
    Scene s = test::floorScene();
    Material unlit = test::lambert(0.7f, 0.3f);
    unlit.shadingModel = 0;
    s.materials.push_back(unlit);
    s.meshes.push_back(test::quad({0, 5, 20}, {1, 0, 0}, {0, 1, 0}, 5.0, 1, 2));  // unlit panel
    s.skyColor = {0.2f, 0.3f, 0.9f};
    Light l;
    l.position = {0, 40, 0};
    l.intensity = 5000.0f;
    s.lights.push_back(l);
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 10, -30}, {0, 5, 20}, {0, 1, 0}, 60.0, 64, 48, 1.0);
    cam.previous = cam.current;
    auto src = test::captureToMemory(s, cam);
    std::vector<NodeDesc> chain = ssgiChain();
    chain.push_back(test::node("ssgi_denoise", {}, {{"diffuse", "ssgi.diffuse"}, {"ao", "ssgi.ao"}}));
    chain.push_back(test::node("diffuse_indirect_composite", {},
                               {{"diffuse", "ssgi_denoise.diffuse"}, {"ao", "ssgi_denoise.ao"}}));
    const auto out = test::runChain(src, chain, {"ssgi.diffuse", "ssgi.ao", "diffuse_indirect_composite.color"});
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    const Plane& model = src.buffers.at("ShadingModel").plane(0);
    const Image& sceneColor = src.buffers.at("SceneColor");
    int sky = 0, unlitPixels = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            const bool isSky = std::isinf(depth.at(x, y));
            if (!isSky && model.at(x, y) != 0.0f) continue;
            (isSky ? sky : unlitPixels)++;
            CHECK(out.at("ssgi.ao").image().plane(0).at(x, y) == 1.0f);
            for (int c = 0; c < 3; ++c) {
                CHECK(out.at("ssgi.diffuse").image().plane(c).at(x, y) == 0.0f);
                CHECK(out.at("diffuse_indirect_composite.color").image().plane(c).at(x, y) ==
                      sceneColor.plane(c).at(x, y));
            }
        }
    CHECK(sky > 100);
    CHECK(unlitPixels > 50);
}

TEST_CASE("half resolution traces half the size and agrees with full resolution on a smooth floor") {
    const int size = 96;
    Scene s = floorAndWall();
    const FrameCamera cam = wallCamera(size);
    auto src = test::captureToMemory(s, cam);
    const auto full = test::runChain(src, ssgiChain(), {"ssgi.ao"});
    const auto half = test::runChain(src, ssgiChain({{"halfRes", true}}), {"ssgi.ao"});
    const Plane& a = full.at("ssgi.ao").image().plane(0);
    const Plane& b = half.at("ssgi.ao").image().plane(0);
    CHECK(b.width() == size / 2);
    CHECK(b.height() == size / 2);
    // Half-res pixel (i, j) traces full-res pixel (2i, 2j) with other random numbers: the two hit
    // fractions differ by noise of variance 2·F(1−F)/32 at most.
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    double sq = 0, noise = 0;
    int n = 0;
    for (int j = 0; j < size / 2; ++j)
        for (int i = 0; i < size / 2; ++i) {
            const Vec3d p = cam.current.worldFromPixel(2 * i, 2 * j, depth.at(2 * i, 2 * j));
            if (std::abs(p.y) > 1e-3 || p.z > 26.0) continue;  // the floor
            const double h = 1.0 - a.at(2 * i, 2 * j);
            sq += (a.at(2 * i, 2 * j) - b.at(i, j)) * (a.at(2 * i, 2 * j) - b.at(i, j));
            noise += 2.0 * std::max(h * (1 - h), 1.0 / 32) / 32;
            ++n;
        }
    REQUIRE(n > 200);
    CHECK(std::sqrt(sq / n) < std::sqrt(noise / n));
}

}  // TEST_SUITE
