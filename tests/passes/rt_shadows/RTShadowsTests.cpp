// rt_shadows: analytic shadows, transmission, packet/scalar and thread identity, SIMD lanes,
// large coordinates and the hard-case floor.
#include "io/scene/SceneLoader.h"
#include "screenspace/Lanes.h"
#include "passes/rt_shadows/RTShadowsKernel.h"
#include "passes/rt_shadows/RTShadowsPass.h"
#include "passes/rt_shadows/ShadowLanes.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <memory>

namespace fp {

TEST_CASE("a sphere's hard shadow on a plane is its analytic silhouette, through Embree and the BVH") {
    // A sun with no source angle, tilted so the camera above sees the shadow beside the sphere:
    // a floor point is in shadow exactly when its ray towards the sun passes within R of the
    // centre. The 256-segment tessellation is within R(1 − cos(π/256)) = 8e-4 units of the sphere.
    const int size = 96;
    const Vec3d travel = normalize(Vec3d{0.8, -1, 0});
    const Scene scene = test::sphereOverFloor({}, test::sun(travel));
    auto src = test::captureToMemory(scene, test::topCamera({}, size));
    for (const std::string traversal : {"embree", "bvh"}) {
        CAPTURE(traversal);
        const auto out = test::runChain(src, {test::node("rt_shadows", {{"traversal", traversal}})},
                                        {"rt_shadows.shadow"});
        const Plane& shadow = out.at("rt_shadows.shadow").image().plane(0);
        const CameraView& cam = src.info.camera.current;
        const Plane& depth = src.buffers.at("SceneDepth").plane(0);
        const Plane& instance = src.buffers.at("InstanceId").plane(0);
        int inside = 0, outside = 0, wrong = 0;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                if (instance.at(x, y) != 1.0f)
                    continue;  // floor pixels only
                const Vec3d p = cam.worldFromPixel(x, y, depth.at(x, y));
                const Vec3d toCentre = Vec3d{0, 30, 0} - p;
                if (dot(toCentre, travel) > 0.0)
                    continue;  // the sphere is behind the light's way
                const double r = length(cross(toCentre, travel));
                // One pixel footprint of margin either side of the edge: a pixel centre that close
                // can fall on either side of a tessellated silhouette.
                const double margin = 2.0 * cam.pixelRadiusAtDepth(depth.at(x, y));
                if (std::fabs(r - test::kSphereRadius) < margin)
                    continue;
                const float expected = r < test::kSphereRadius ? 0.0f : 1.0f;
                (expected == 0.0f ? inside : outside)++;
                wrong += shadow.at(x, y) != expected;
            }
        CHECK(inside > 200);
        CHECK(outside > 2000);
        CHECK(wrong == 0);
    }
}

TEST_CASE("transmission through a slab is exp(−density·thickness)") {
    // A subsurface slab (model 2) 1 m × 1 m, `thickness` cm deep, faces the camera; the sun shines
    // through it from behind. Its pixels' shadow rays are blocked by the slab itself, and the
    // inverted ray measures the slab: T = exp(0.05·ln(1 − opacity)·d) = (1 − opacity)^(0.05·d).
    for (const auto& slab : {std::pair{0.5f, 20.0}, std::pair{0.9f, 10.0}}) {
        // (Named variables: clang 14 cannot capture a structured binding, as INFO does.)
        const float opacity = slab.first;
        const double thickness = slab.second;
        Scene s;
        s.sceneUnitsPerMeter = 100.0;
        Material m = test::lambert(0.5f);
        m.shadingModel = 2;
        m.opacity = opacity;
        s.materials.push_back(m);
        // Front face at z = 0 (facing −z, the camera), back face at z = thickness.
        s.meshes.push_back(test::quad({0, 0, 0}, {0, 1, 0}, {1, 0, 0}, 50.0, 0, 7));
        s.meshes.push_back(test::quad({0, 0, thickness}, {1, 0, 0}, {0, 1, 0}, 50.0, 0, 7));
        s.lights.push_back(test::sun({0, 0, -1}));  // travelling towards the camera
        FrameCamera cam;
        cam.current = CameraView::lookAt({0, 0, -300}, {0, 0, 0}, {0, 1, 0}, 10.0, 32, 32, 10.0);
        cam.previous = cam.current;
        auto src = test::captureToMemory(s, cam);
        const auto out =
            test::runChain(src, {test::node("rt_shadows")}, {"rt_shadows.transmission", "rt_shadows.shadow"});
        const Plane& T = out.at("rt_shadows.transmission").image().plane(0);
        const Plane& V = out.at("rt_shadows.shadow").image().plane(0);
        const double expected = std::pow(1.0 - opacity, 0.05 * thickness);
        INFO("opacity " << opacity << ", thickness " << thickness << " cm: " << expected);
        CHECK(shadow::transmittance(opacity, float(thickness)) ==
              doctest::Approx(expected).epsilon(1e-5));
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                // The ray starts within the 0.1 cm bias of the front face: at most 0.1 cm of slab
                // more or less, a relative change of 0.05·|ln(1 − opacity)|·0.1.
                const double tol = 0.05 * std::fabs(std::log(1.0 - opacity)) * 0.1 * expected;
                CHECK(T.at(x, y) == doctest::Approx(expected).epsilon(tol / expected + 1e-5));
                CHECK(V.at(x, y) == 0.0f);  // blocked, and T < 1: not promoted
            }
    }
}

namespace {
// A sphere light over a floor and a subsurface sphere (opacity 0.4), seen from above and in front;
// the capture points at the scene, so both live together.
struct SoftShadowCapture {
    Scene scene;
    test::MemorySource src;
};
std::unique_ptr<SoftShadowCapture> softShadowCapture(int width, int height) {
    auto c = std::make_unique<SoftShadowCapture>();
    Light bulb;
    bulb.name = "bulb";
    bulb.position = {20, 80, -10};
    bulb.radius = 15.0f;
    bulb.intensity = 5000.0f;
    Scene& scene = c->scene = test::sphereOverFloor({}, bulb);
    Material skin = test::lambert(0.7f);
    skin.shadingModel = 2;
    skin.opacity = 0.4f;
    scene.materials.push_back(skin);
    scene.meshes[1].material = 1;
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 90, -120}, {0, 10, 0}, {0, 1, 0}, 40.0, width, height, 10.0);
    cam.previous = cam.current;
    c->src = test::captureToMemory(scene, cam);
    return c;
}
}  // namespace

TEST_CASE("packets and single rays agree bit for bit; 1 and 2 threads are byte-identical") {
    // Soft shadows of a sphere light (4 samples per pixel) over a floor and a subsurface sphere,
    // so occlusion, closest-hit distances and transmission rays all take both paths.
    const auto capture = softShadowCapture(80, 64);
    auto& src = capture->src;
    const std::vector<std::string> outs = {"rt_shadows.shadow", "rt_shadows.transmission",
                                           "rt_shadows.hitDistance", "rt_shadows.lightAttenuation"};
    auto trace = [&](bool packets, int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return test::runChain(src,
                   {test::node("rt_shadows", {{"rayPackets", packets}, {"samplesPerPixel", 4}})},
                   outs);
    };
    const auto packet = trace(true, 2), scalar = trace(false, 2), oneThread = trace(true, 1);
    for (const auto& o : outs) {
        const Image& a = packet.at(o).image();
        for (int c = 0; c < a.channelCount(); ++c) {
            CHECK_MESSAGE(test::sameBits(a.plane(c), scalar.at(o).image().plane(c)), o);
            CHECK_MESSAGE(test::sameBits(a.plane(c), oneThread.at(o).image().plane(c)), o);
        }
    }
    // The scene has penumbrae and transmission: the comparison is not between empty images.
    const Plane& s = packet.at("rt_shadows.shadow").image().plane(0);
    int partial = 0;
    for (int y = 0; y < s.height(); ++y)
        for (int x = 0; x < s.width(); ++x)
            partial += s.at(x, y) > 0.0f && s.at(x, y) < 1.0f;
    CHECK(partial > 20);
}

TEST_CASE("the BVH path, the GPU's code, gives Embree's shadows but where a ray grazes an edge") {
    // The scene of the packet test: soft shadows of a sphere light (4 samples per pixel) over a
    // floor and a subsurface sphere, so occlusion, closest hits and transmission rays all run.
    const auto capture = softShadowCapture(160, 128);
    auto& src = capture->src;
    const std::vector<std::string> outs = {"rt_shadows.shadow", "rt_shadows.transmission",
                                           "rt_shadows.hitDistance", "rt_shadows.lightAttenuation"};
    auto trace = [&](const std::string& traversal, int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        return test::runChain(
            src, {test::node("rt_shadows", {{"traversal", traversal}, {"samplesPerPixel", 4}})},
            outs);
    };
    const auto embree = trace("embree", 2), bvh = trace("bvh", 2), oneThread = trace("bvh", 1);
    for (const auto& o : outs)
        for (int c = 0; c < bvh.at(o).image().channelCount(); ++c)
            CHECK_MESSAGE(test::sameBits(bvh.at(o).image().plane(c), oneThread.at(o).image().plane(c)), o);
    const Plane& se = embree.at("rt_shadows.shadow").image().plane(0);
    const Plane& sb = bvh.at("rt_shadows.shadow").image().plane(0);
    const Plane& te = embree.at("rt_shadows.transmission").image().plane(0);
    const Plane& tb = bvh.at("rt_shadows.transmission").image().plane(0);
    const Plane& he = embree.at("rt_shadows.hitDistance").image().plane(0);
    const Plane& hb = bvh.at("rt_shadows.hitDistance").image().plane(0);
    int pixels = 0, shadowDiffers = 0, partial = 0;
    double transmissionDiff = 0.0, distanceRel = 0.0;
    for (int y = 0; y < se.height(); ++y)
        for (int x = 0; x < se.width(); ++x) {
            ++pixels;
            partial += se.at(x, y) > 0.0f && se.at(x, y) < 1.0f;
            if (se.at(x, y) != sb.at(x, y)) {
                ++shadowDiffers;  // some ray of the pixel decided the other way
                continue;
            }
            transmissionDiff = std::max(transmissionDiff, double(std::fabs(te.at(x, y) - tb.at(x, y))));
            CHECK((he.at(x, y) < 0.0f) == (hb.at(x, y) < 0.0f));
            if (he.at(x, y) > 0.0f)
                distanceRel = std::max(distanceRel, std::fabs(double(he.at(x, y)) - hb.at(x, y)) /
                                                        double(he.at(x, y)));
        }
    MESSAGE("pixels " << pixels << ": shadow differs at " << shadowDiffers << "; transmission within "
                      << transmissionDiff << ", closest occluder within " << distanceRel << " relative");
    CHECK(partial > 100);
    // A pixel differs only where one of its 4 rays passes within a few float steps of a
    // triangle's edge (the two triangle tests round differently there): a silhouette edge is
    // 10⁻⁵ of a pixel wide, so a handful of the 20k pixels at most.
    CHECK(shadowDiffers <= pixels / 1000);
    // The thickness is the difference of two distances near 150 units, each within a few float
    // steps (10⁻⁵ units) of exact: transmission moves by density·10⁻⁵ cm at most.
    CHECK(transmissionDiff <= 1e-5);
    CHECK(distanceRel <= 1e-5);
}

TEST_CASE("set-up and rays in SIMD lanes give the scalar reference's bits for every light type") {
    // A floor under three spheres: subsurface (2), hair (7) and subsurface profile (5), so the
    // back-side bias, the hair normal and both transmission kinds take part; every light type,
    // the local ones with an attenuation radius that leaves part of the floor out of reach and
    // (spot) a cone that leaves out more. Two samples a pixel: the second reads each lane's
    // advanced random stream.
    Light sunLight = test::sun({0.3, -1, 0.2}, 4.0f);
    Light bulb;
    bulb.name = "bulb";
    bulb.position = {20, 80, -10};
    bulb.radius = 15.0f;
    bulb.attenuationRadius = 140.0;
    Light spot = bulb;
    spot.name = "spot";
    spot.type = LightType::Spot;
    spot.direction = {0, -1, 0.2};
    spot.outerConeDegrees = 35.0f;
    Light panel;
    panel.name = "panel";
    panel.type = LightType::Rect;
    panel.position = {-10, 90, 0};
    panel.direction = {0, -1, 0};
    panel.halfU = {20, 0, 0};
    panel.halfV = {0, 0, 15};  // halfU × halfV points down: it lights the floor
    panel.attenuationRadius = 160.0;
    Scene scene = test::sphereOverFloor({}, sunLight);
    scene.lights = {sunLight, bulb, spot, panel};
    for (const int model : {2, 7, 5}) {
        Material m = test::lambert(0.6f);
        m.shadingModel = model;
        m.opacity = 0.5f;
        scene.materials.push_back(m);
    }
    scene.meshes[1].material = 1;  // the subsurface sphere of sphereOverFloor
    scene.meshes.push_back(test::sphere({-35, 12, 15}, 12.0, 48, 2, 3));
    scene.meshes.push_back(test::sphere({35, 12, 20}, 12.0, 48, 3, 4));
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 90, -130}, {0, 10, 0}, {0, 1, 0}, 60.0, 83, 61, 10.0);
    cam.previous = cam.current;
    auto src = test::captureToMemory(scene, cam);
    const std::vector<std::string> outs = {"rt_shadows.shadow", "rt_shadows.transmission",
                                           "rt_shadows.hitDistance", "rt_shadows.lightAttenuation"};
    const std::vector<int64_t> targets = laneTargetsHere();
    REQUIRE(!targets.empty());
    int compared = 0;
    for (const Light& light : scene.lights) {
        auto trace = [&](bool lanes, int64_t target) {
            useOnlyLaneTarget(target);
            test::MemorySink sink;
            const NodeDesc node = test::node(
                "rt_shadows", {{"light", light.name}, {"lanes", lanes}, {"samplesPerPixel", 2}});
            const FrameReport report = executePlan(test::planFor({node}, outs), src, sink);
            useOnlyLaneTarget(0);
            return std::pair{sink.layers, report.passes.back().work};
        };
        const auto [scalar, scalarWork] = trace(false, 0);
        // Both branches of the light's reach and of N·L culling are compared.
        CHECK_MESSAGE(scalarWork.at("pixels") > 500, light.name);
        if (light.type != LightType::Directional)
            CHECK_MESSAGE(scalarWork.at("skippedPixels") > 200, light.name);
        CHECK_MESSAGE(scalarWork.at("transmissionRays") > 100, light.name);
        for (int64_t target : targets) {
            INFO(light.name, ", target ", target);
            const auto [lanes, lanesWork] = trace(true, target);
            CHECK(lanesWork == scalarWork);
            for (const auto& o : outs) {
                const Image& a = lanes.at(o).image();
                for (int c = 0; c < a.channelCount(); ++c)
                    CHECK_MESSAGE(test::sameBits(a.plane(c), scalar.at(o).image().plane(c)), o);
            }
            ++compared;
        }
    }
    CHECK(compared == 4 * int(targets.size()));
}

TEST_CASE("a camera 10^7 units from the origin sees the same shadows as one at the origin") {
    const Light l = test::sun({0.3, -1, 0.2}, 0.5357f);
    const Vec3d far{1e7, 0, -1e7};
    const Scene near = test::sphereOverFloor({}, l), away = test::sphereOverFloor(far, l);
    auto a = test::captureToMemory(near, test::topCamera({}, 64));
    auto b = test::captureToMemory(away, test::topCamera(far, 64));
    const auto sa = test::runChain(a, {test::node("rt_shadows")}, {"rt_shadows.shadow"});
    const auto sb = test::runChain(b, {test::node("rt_shadows")}, {"rt_shadows.shadow"});
    // Geometry is stored relative to the eye and positions are rebuilt camera-relative, so
    // the far scene's rays are the near scene's up to the rounding of the offsets (double).
    const Plane& pa = sa.at("rt_shadows.shadow").image().plane(0);
    const Plane& pb = sb.at("rt_shadows.shadow").image().plane(0);
    int differ = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            differ += pa.at(x, y) != pb.at(x, y);
    CHECK(differ == 0);
}

TEST_CASE("no shadow acne on the hard-case scene's grazing floor at Unreal's default bias") {
    // The hard scene's floor alone, 10^7 units from the origin, seen at grazing angles from 20 cm
    // above: nothing can shadow it, so every floor pixel must be lit, with the scene's sun (45°)
    // and with a sun 2° above the horizon.
    io::SceneFile sf = io::loadScene(std::string(FP_SOURCE_DIR) + "/examples/hard/scene.json");
    Scene floorOnly = sf.scene;
    floorOnly.meshes.erase(std::remove_if(floorOnly.meshes.begin(), floorOnly.meshes.end(),
                                          [](const Mesh& m) { return m.name != "floor"; }),
                           floorOnly.meshes.end());
    REQUIRE(floorOnly.meshes.size() == 1);
    const FrameCamera cam = sf.cameraForFrame(1, {128, 128});
    for (const double elevation : {45.0, 2.0}) {
        Scene s = floorOnly;
        s.lights.clear();
        const double e = elevation * kPi / 180.0;
        s.lights.push_back(test::sun({0.0, -std::sin(e), -std::cos(e)}));
        auto src = test::captureToMemory(s, cam);
        const auto out = test::runChain(src, {test::node("rt_shadows")}, {"rt_shadows.shadow"});
        const Plane& shadow = out.at("rt_shadows.shadow").image().plane(0);
        const Plane& depth = src.buffers.at("SceneDepth").plane(0);
        int floorPixels = 0, acne = 0;
        for (int y = 0; y < 128; ++y)
            for (int x = 0; x < 128; ++x) {
                if (std::isinf(depth.at(x, y)))
                    continue;
                ++floorPixels;
                acne += shadow.at(x, y) != 1.0f;
            }
        INFO("test::sun elevation " << elevation);
        CHECK(floorPixels > 4000);
        CHECK(acne == 0);
    }
}

}  // namespace fp
