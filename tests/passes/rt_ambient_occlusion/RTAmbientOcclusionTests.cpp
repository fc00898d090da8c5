// rt_ambient_occlusion against analytic answers: an open floor, a closed sphere, a floor beside an
// infinite wall (the cosine-weighted fraction of rays that reach it within the radius), the
// shading/geometric lobe overlap, thread identity, the SIMD lanes against the scalar reference,
// and the BVH path (the GPU's code) against Embree's packets.
#include "passes/rt_ambient_occlusion/RTAmbientOcclusionKernel.h"
#include "screenspace/Lanes.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

namespace fp {

namespace {

// The pass's outputs on `src`.
std::map<std::string, Texture> runAo(test::MemorySource& src, nlohmann::json params) {
    return test::runChain(src, {test::node("rt_ambient_occlusion", std::move(params))},
                          {"rt_ambient_occlusion.ao", "rt_ambient_occlusion.hitDistance"});
}

// A floor (y = 0) in centimetres, seen from straight above.
Scene floorInCm() {
    Scene s = test::floorScene();
    s.sceneUnitsPerMeter = 100.0;
    return s;
}

// The cosine-weighted fraction of the hemisphere over a floor point whose rays of length R reach
// a wall (infinite, perpendicular to the floor) at distance h: a ray reaches it when its
// horizontal component towards the wall is at least a = h/R, and cosine-weighted directions
// project uniformly onto the unit disk, so the fraction is the area of the disk's segment
// x ≥ a over π.
double wallFraction(double h, double R) {
    const double a = h / R;
    if (a >= 1.0) return 0.0;
    return (std::acos(a) - a * std::sqrt(1.0 - a * a)) / kPi;
}

}  // namespace

TEST_CASE("rt_ambient_occlusion: an open floor is unoccluded, its hit distance Unreal's 'none'") {
    const Scene scene = floorInCm();
    auto src = test::captureToMemory(scene, test::topCamera({}, 32));
    const auto out = runAo(src, {{"samplesPerPixel", 4}});
    const Plane& ao = out.at("rt_ambient_occlusion.ao").image().plane(0);
    const Plane& hit = out.at("rt_ambient_occlusion.hitDistance").image().plane(0);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            // The normal rebuilt from depth differs from the exact one by rounding only; the lobe
            // overlap is flat at equal normals, so the AO is 1 to second order.
            CHECK(ao.at(x, y) == doctest::Approx(1.0).epsilon(1e-5));
            CHECK(ao.at(x, y) <= 1.0f);
            CHECK(hit.at(x, y) == rtao::kNoHitCm);  // 1 scene unit a centimetre
        }
}

TEST_CASE("rt_ambient_occlusion: inside a closed sphere smaller than the radius every ray is blocked") {
    Scene scene;
    scene.sceneUnitsPerMeter = 100.0;
    scene.materials.push_back(test::lambert(0.5f));
    scene.meshes.push_back(test::sphere({0, 0, 0}, 50.0, 64));
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 0, 0}, {1, 0.3, 0.2}, {0, 1, 0}, 60.0, 24, 24, 1.0);
    cam.previous = cam.current;
    auto src = test::captureToMemory(scene, cam);
    for (const float intensity : {1.0f, 0.25f}) {
        CAPTURE(intensity);
        const auto out = runAo(src, {{"samplesPerPixel", 8}, {"radius", 200.0}, {"intensity", intensity}});
        const Plane& ao = out.at("rt_ambient_occlusion.ao").image().plane(0);
        const Plane& hit = out.at("rt_ambient_occlusion.hitDistance").image().plane(0);
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                // Every ray counts 1 − intensity; the lobe overlap (≤ 1) scales it.
                CHECK(ao.at(x, y) <= 1.0f - intensity + 1e-6f);
                if (intensity == 1.0f) CHECK(ao.at(x, y) == 0.0f);
                CHECK(hit.at(x, y) > 0.0f);
                CHECK(hit.at(x, y) <= 100.0f + 1.0f);  // within the sphere's diameter
            }
    }
}

TEST_CASE("rt_ambient_occlusion: beside an infinite wall, the analytic cosine fraction within the radius") {
    // The floor y = 0 and a wall x = 30 (facing −x), both 20 m across: within a radius of 40 cm
    // they are infinite. A floor pixel at distance h from the wall loses wallFraction(h, 40) of its
    // rays; h ≥ 40 loses none.
    Scene scene = floorInCm();
    scene.meshes.push_back(test::quad({30, 0, 0}, {0, 0, 1}, {0, 1, 0}, 1000.0, 0, 2));
    scene.meshes[0] = test::quad({}, {1, 0, 0}, {0, 0, -1}, 1000.0, 0, 1);
    const int size = 48;
    auto src = test::captureToMemory(scene, test::topCamera({}, size));
    const int spp = 64;
    const double R = 40.0;
    const auto out = runAo(src, {{"samplesPerPixel", spp}, {"radius", R}});
    const Plane& ao = out.at("rt_ambient_occlusion.ao").image().plane(0);
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    const Plane& instance = src.buffers.at("InstanceId").plane(0);
    const CameraView& cam = src.info.camera.current;
    double measured = 0, expected = 0, variance = 0;
    int near = 0, far = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            if (instance.at(x, y) != 1.0f) continue;  // floor pixels
            const Vec3d p = cam.worldFromPixel(x, y, depth.at(x, y));
            const double h = 30.0 - p.x;
            if (h < 1.0) continue;  // the wall's foot: the bias moves these rays
            const double f = wallFraction(h, R);
            if (f == 0.0) {
                CHECK(ao.at(x, y) == doctest::Approx(1.0).epsilon(1e-5));
                ++far;
                continue;
            }
            measured += ao.at(x, y);
            expected += 1.0 - f;
            variance += f * (1.0 - f) / spp;  // a pixel's mean of spp Bernoulli rays
            ++near;
        }
    REQUIRE(near > 200);
    REQUIRE(far > 100);
    // The mean over the near pixels within 4 standard deviations of the rays' noise.
    const double sigma = std::sqrt(variance) / near;
    CAPTURE(sigma);
    CHECK(std::fabs(measured / near - expected / near) < 4.0 * sigma);
    CHECK(sigma < 0.01);  // the test can tell the AO apart from a wrong one
}

TEST_CASE("rt_ambient_occlusion: the shading lobe's overlap with the geometric one") {
    const Vec3f up{0, 1, 0};
    CHECK(rtao::lobeOverlap(up, up) == doctest::Approx(1.0f));
    // Perpendicular normals: (sinh(λ√2)/(λ√2))·(2λ/sinh(2λ)) with λ = 2.133.
    const double l = rtao::kCosineLobeSharpness, d = l * std::sqrt(2.0);
    const double expected = (std::sinh(d) / d) * (2.0 * l / std::sinh(2.0 * l));
    CHECK(rtao::lobeOverlap(up, Vec3f{1, 0, 0}) == doctest::Approx(expected).epsilon(1e-6));
    CHECK(rtao::lobeOverlap(up, -up) == doctest::Approx(2.0 * l / std::sinh(2.0 * l)).epsilon(1e-6));
    // Less overlap the further apart.
    CHECK(rtao::lobeOverlap(up, normalize(Vec3f{1, 1, 0})) > rtao::lobeOverlap(up, Vec3f{1, 0, 0}));
}

TEST_CASE("rt_ambient_occlusion: 1 and 2 threads give the same bits") {
    Scene scene = floorInCm();
    scene.meshes.push_back(test::sphere({0, 12, 0}, 10.0, 64, 0, 2));
    auto src = test::captureToMemory(scene, test::topCamera({}, 64));
    std::map<std::string, Texture> outs[2];
    for (int threads : {1, 2}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        outs[threads - 1] = runAo(src, {{"samplesPerPixel", 4}});
    }
    for (const char* name : {"rt_ambient_occlusion.ao", "rt_ambient_occlusion.hitDistance"})
        CHECK(test::sameBits(outs[0].at(name).image().plane(0), outs[1].at(name).image().plane(0)));
    // The sphere occludes the floor around its foot: some AO below 1, none above.
    const Plane& ao = outs[0].at("rt_ambient_occlusion.ao").image().plane(0);
    float lowest = 1.0f;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) lowest = std::min(lowest, ao.at(x, y));
    CHECK(lowest < 0.9f);
}

TEST_CASE("rt_ambient_occlusion: set-up and rays in SIMD lanes give the scalar reference's bits") {
    // A floor in centimetres under three spheres — one lambert, one two-sided foliage (its
    // geometric normal is the shading one), one unlit (skipped) — seen at an angle so the frame
    // holds sky (skipped, and no neighbour for the pixels beside it), the image's edges (a side
    // with one neighbour) and silhouettes (the shorter difference chosen); a width that is no
    // multiple of any vector width; two samples a pixel, so the second reads each lane's advanced
    // stream; every instruction set the build has lanes for that this CPU runs.
    Scene scene = floorInCm();
    for (const int model : {6, 0}) {  // two-sided foliage, unlit
        Material m = test::lambert(0.6f);
        m.shadingModel = model;
        scene.materials.push_back(m);
    }
    scene.meshes.push_back(test::sphere({-30, 12, 20}, 12.0, 48, 0, 2));
    scene.meshes.push_back(test::sphere({0, 12, 25}, 12.0, 48, 1, 3));
    scene.meshes.push_back(test::sphere({30, 12, 20}, 12.0, 48, 2, 4));
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 40, -60}, {0, 10, 40}, {0, 1, 0}, 70.0, 83, 61, 10.0);
    cam.previous = cam.current;
    auto src = test::captureToMemory(scene, cam);
    const std::vector<std::string> outs = {"rt_ambient_occlusion.ao", "rt_ambient_occlusion.hitDistance"};
    auto trace = [&](bool lanes, int64_t target) {
        useOnlyLaneTarget(target);
        test::MemorySink sink;
        const NodeDesc node = test::node("rt_ambient_occlusion",
                                         {{"lanes", lanes}, {"samplesPerPixel", 2}, {"radius", 40.0}});
        const FrameReport report = executePlan(test::planFor({node}, outs), src, sink);
        useOnlyLaneTarget(0);
        return std::pair{sink.layers, report.passes.back().work};
    };
    const auto [scalar, scalarWork] = trace(false, 0);
    CHECK(scalarWork.at("pixels") > 2000);
    CHECK(scalarWork.at("skippedPixels") > 200);
    const std::vector<int64_t> targets = laneTargetsHere();
    REQUIRE(!targets.empty());
    for (int64_t target : targets) {
        INFO("target ", target);
        const auto [lanes, lanesWork] = trace(true, target);
        CHECK(lanesWork == scalarWork);
        for (const auto& o : outs)
            CHECK_MESSAGE(test::sameBits(lanes.at(o).image().plane(0), scalar.at(o).image().plane(0)), o);
    }
    // Some AO below 1 (the spheres occlude the floor) and above 0: the comparison is not trivial.
    const Plane& ao = scalar.at("rt_ambient_occlusion.ao").image().plane(0);
    float lowest = 1.0f;
    for (int y = 0; y < ao.height(); ++y)
        for (int x = 0; x < ao.width(); ++x) lowest = std::min(lowest, ao.at(x, y));
    CHECK(lowest < 0.9f);
}

TEST_CASE("rt_ambient_occlusion: the BVH path, the GPU's code, gives Embree's AO but where a ray grazes an edge") {
    // A sphere resting on the floor, 4 samples a pixel: open, partly and wholly occluded pixels,
    // and a closest hit for every blocked ray.
    Scene scene = floorInCm();
    scene.meshes.push_back(test::sphere({0, 12, 0}, 10.0, 64, 0, 2));
    auto src = test::captureToMemory(scene, test::topCamera({}, 96));
    auto trace = [&](const std::string& traversal, int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return runAo(src, {{"samplesPerPixel", 4}, {"traversal", traversal}});
    };
    const auto embree = trace("embree", 2), bvh = trace("bvh", 2), oneThread = trace("bvh", 1);
    for (const char* name : {"rt_ambient_occlusion.ao", "rt_ambient_occlusion.hitDistance"})
        CHECK(test::sameBits(bvh.at(name).image().plane(0), oneThread.at(name).image().plane(0)));
    const Plane& ae = embree.at("rt_ambient_occlusion.ao").image().plane(0);
    const Plane& ab = bvh.at("rt_ambient_occlusion.ao").image().plane(0);
    const Plane& he = embree.at("rt_ambient_occlusion.hitDistance").image().plane(0);
    const Plane& hb = bvh.at("rt_ambient_occlusion.hitDistance").image().plane(0);
    int pixels = 0, differs = 0, occluded = 0;
    double distanceRel = 0.0;
    for (int y = 0; y < ae.height(); ++y)
        for (int x = 0; x < ae.width(); ++x) {
            ++pixels;
            occluded += ae.at(x, y) < 0.99f;
            if (ae.at(x, y) != ab.at(x, y)) {
                ++differs;  // some ray of the pixel decided the other way
                continue;
            }
            // Where every ray decided alike the closest hit is the same triangle's, computed by
            // two triangle tests within a few float steps (6e-8 relative) of the coordinates,
            // which here are at most ~10× the distances: 1e-5.
            if (he.at(x, y) > 0.0f)
                distanceRel = std::max(distanceRel, std::fabs(double(he.at(x, y)) - hb.at(x, y)) /
                                                        double(he.at(x, y)));
            else
                CHECK(hb.at(x, y) == he.at(x, y));
        }
    MESSAGE("pixels " << pixels << ": AO differs at " << differs << ", occluded " << occluded
                      << "; closest hit within " << distanceRel << " relative");
    CHECK(occluded > 200);
    // A pixel differs only where one of its 4 rays passes within a few float steps of a
    // triangle's edge: at most one pixel in a thousand (rt_shadows' bound).
    CHECK(differs * 1000 <= pixels);
    CHECK(distanceRel <= 1e-5);
}

}  // namespace fp
