// rt_reflections against analytic answers: a mirror floor shows a point-lit Lambert wall's
// radiance ρ/π·I·cosθ/r²; under an open sky it shows the sky; the roughness fade sets the
// coverage; a light's visible shape is not reflected as emission (the light's specular is).
// Each case runs the BVH path (traversal "bvh", the GPU's code) too and checks it against Embree's.
#include "io/scene/SceneLoader.h"
#include "tests/support/LaneTargets.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <set>
#include <tuple>
#include <vector>

namespace fp {

namespace {

// The pass's outputs through Embree — and, where the BVH path (the GPU's code) takes the same
// settings, its outputs checked against them: the same random numbers draw the same rays, which
// decide alike unless one passes within a few float steps of an edge; a hit's position and
// barycentrics round differently in their last bits, so values agree to 10⁻⁴ relative (a few
// float steps carried through the lighting) at all but one pixel in a hundred.
std::map<std::string, Texture> runRtr(test::MemorySource& src, nlohmann::json params = nlohmann::json::object()) {
    const std::vector<std::string> outputs = {"rt_reflections.reflection", "rt_reflections.hitDistance"};
    auto embree = test::runChain(src, {test::node("rt_reflections", params)}, outputs);
    const bool skyAlongPaths = params.value("hitIndirectBounces", 0) > 0 &&
                               src.sceneData && src.sceneData->environment.sky.enabled;
    if (skyAlongPaths) return embree;  // traversal "bvh" refuses it
    nlohmann::json bvhParams = params;
    bvhParams["traversal"] = "bvh";
    const auto bvh = test::runChain(src, {test::node("rt_reflections", bvhParams)}, outputs);
    for (const std::string& o : outputs) {
        const Image& a = embree.at(o).image();
        const Image& b = bvh.at(o).image();
        int differs = 0;
        for (int y = 0; y < a.height(); ++y)
            for (int x = 0; x < a.width(); ++x)
                for (int c = 0; c < a.channelCount(); ++c) {
                    const double va = a.plane(c).at(x, y), vb = b.plane(c).at(x, y);
                    if (std::fabs(va - vb) > 1e-4 * std::max(std::fabs(va), 1e-6)) {
                        ++differs;
                        break;
                    }
                }
        INFO(o << ": the BVH path differs beyond 1e-4 at " << differs << " pixels");
        CHECK(differs * 100 <= a.width() * a.height());
    }
    return embree;
}

FrameCamera camera(const Vec3d& eye, const Vec3d& target, int w, int h, double fov) {
    FrameCamera cam;
    cam.current = CameraView::lookAt(eye, target, {0, 1, 0}, fov, w, h, 0.01);
    cam.previous = cam.current;
    return cam;
}

}  // namespace

TEST_CASE("rt_reflections: a mirror floor shows the point-lit wall's radiance") {
    // The truth tracer's test scene: a mirror floor (roughness 0: the mirror ray) before a Lambert
    // wall (ρ = 0.6) lit by a spot whose inner cone covers the tested part of the wall. A floor
    // pixel's reflection is the wall's radiance ρ/π·I·cosθ/r² at the mirrored point, coverage 1.
    Scene s;
    s.materials.push_back(test::mirror());
    s.materials.push_back(test::lambert(0.6f));
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 100.0, 0, 1));  // floor y = 0
    s.meshes.push_back(test::quad({0, 50, 60}, {1, 0, 0}, {0, 1, 0}, 50.0, 1, 2));  // wall z = 60
    Light l;
    l.name = "spot";
    l.type = LightType::Spot;
    l.position = {10, 40, 20};
    l.direction = {0, 0, 1};
    l.innerConeDegrees = 30.0f;
    l.outerConeDegrees = 35.0f;
    l.intensity = 5000.0f;
    s.lights.push_back(l);
    const FrameCamera cam = camera({0, 20, -40}, {0, 5, 30}, 32, 24, 50.0);
    auto src = test::captureToMemory(s, cam);
    const auto out = runRtr(src);
    const Image& r = out.at("rt_reflections.reflection").image();
    const CameraView& c = cam.current;
    int checked = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const Vec3d d = c.rayDirection(x, y);
            if (d.y >= 0) continue;
            const Vec3d p = c.position + d * (-c.position.y / d.y);  // on the floor
            const Vec3d m{d.x, -d.y, d.z};                           // mirrored direction
            // The ray leaves from the floor point moved as Unreal moves it (algorithms §9.2):
            // 0.1 towards the camera, then up by lerp(0.1, 0.01, N·L).
            const Vec3d o = p - d * 0.1 + Vec3d{0, 1, 0} * (0.1 + (0.01 - 0.1) * m.y);
            const Vec3d w = o + m * ((60.0 - o.z) / m.z);            // on the wall
            if (m.z <= 0 || std::abs(w.x) > 45 || w.y < 5 || w.y > 95) continue;
            const Vec3d toLight = l.position - w;
            const double r2 = dot(toLight, toLight), cosTheta = -toLight.z / std::sqrt(r2);
            if (cosTheta < std::cos(29.0 * kPi / 180.0)) continue;  // outside the inner cone
            const double expected = 0.6 / kPi * l.intensity * cosTheta / r2;
            // To the float rounding of the position rebuilt from depth and of the shading.
            CHECK(r.plane(1).at(x, y) == doctest::Approx(expected).epsilon(2e-4));
            CHECK(r.plane(3).at(x, y) == 1.0f);
            ++checked;
        }
    CHECK(checked > 60);
}

TEST_CASE("rt_reflections: under an open sky a mirror shows the sky, and the fade sets the coverage") {
    Scene s;
    s.materials.push_back(test::mirror());
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 1000.0, 0, 1));
    s.environment.sky.enabled = true;
    s.environment.sky.color = {0.25f, 0.5f, 1.0f};
    auto src = test::captureToMemory(s, camera({0, 20, -40}, {0, 0, 0}, 16, 16, 40.0));
    const auto out = runRtr(src);
    const Image& r = out.at("rt_reflections.reflection").image();
    const Plane& hit = out.at("rt_reflections.hitDistance").image().plane(0);
    // A constant sky's cubemap is that colour at every mip (to float rounding of its filter).
    CHECK(r.plane(0).at(8, 12) == doctest::Approx(0.25).epsilon(1e-4));
    CHECK(r.plane(2).at(8, 12) == doctest::Approx(1.0).epsilon(1e-4));
    CHECK(r.plane(3).at(8, 12) == 1.0f);
    CHECK(hit.at(8, 12) == 1e20f);

    // Roughness 0.45 under the cutoff 0.6: fade 2 − 2·0.45/0.6 = 0.5, on colour and coverage.
    s.materials[0].roughness = 0.45f;
    auto rough = test::captureToMemory(s, camera({0, 20, -40}, {0, 0, 0}, 16, 16, 40.0));
    const auto faded = runRtr(rough, {{"samplesPerPixel", 4}});
    const Image& f = faded.at("rt_reflections.reflection").image();
    CHECK(f.plane(3).at(8, 12) == doctest::Approx(0.5f));
    CHECK(f.plane(0).at(8, 12) == doctest::Approx(0.125).epsilon(1e-3));
    // Past the cutoff nothing is traced: 0 and −2.
    const auto none = runRtr(rough, {{"maxRoughness", 0.4}});
    CHECK(none.at("rt_reflections.reflection").image().plane(3).at(8, 12) == 0.0f);
    CHECK(none.at("rt_reflections.hitDistance").image().plane(0).at(8, 12) == -2.0f);
}

TEST_CASE("rt_reflections: a hit's traced indirect light sees the sky only where the scene opens") {
    // A mirror floor (y = 0, half-size 10⁵) before a Lambert wall (ρ = 0.6, z = 60) under a
    // constant sky L = 1, no lights. Unreal's hit lighting (hitIndirectBounces 0) gives the wall
    // the sky's SH irradiance/π, unshadowed: ρ·L = 0.6 (SH holds a constant exactly). Traced, the
    // wall's cosine hemisphere sees the sky above the horizon and the floor below it, whose
    // diffuse colour is 0 (a metal): ρ·L·½ = 0.3, the floor's far edge lowering the horizon by
    // under 0.06° (a 5·10⁻⁴ share). Enclosed in a black box, the traced light is exactly 0 while
    // the SH still gives 0.6.
    Scene s;
    s.materials.push_back(test::mirror());
    s.materials.push_back(test::lambert(0.6f));
    s.materials.push_back(test::lambert(0.0f));
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 1e5, 0, 1));    // floor y = 0
    s.meshes.push_back(test::quad({0, 50, 60}, {1, 0, 0}, {0, 1, 0}, 50.0, 1, 2));  // wall z = 60
    s.environment.sky.enabled = true;
    s.environment.sky.color = {1, 1, 1};
    const FrameCamera cam = camera({0, 20, -40}, {0, 5, 30}, 32, 24, 50.0);
    const CameraView& c = cam.current;
    // The floor pixels whose mirror ray meets the wall away from its edges.
    std::vector<std::pair<int, int>> onWall;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const Vec3d d = c.rayDirection(x, y);
            if (d.y >= 0) continue;
            const Vec3d p = c.position + d * (-c.position.y / d.y);
            const Vec3d m{d.x, -d.y, d.z};
            const Vec3d w = p + m * ((60.0 - p.z) / m.z);
            if (m.z > 0 && std::abs(w.x) < 45 && w.y > 5 && w.y < 95) onWall.emplace_back(x, y);
        }
    REQUIRE(onWall.size() > 60);
    auto meanOnWall = [&](const Scene& scene, int bounces) {
        auto src = test::captureToMemory(scene, cam);
        const auto out = runRtr(src, {{"samplesPerPixel", 64}, {"hitIndirectBounces", bounces}});
        const Plane& g = out.at("rt_reflections.reflection").image().plane(1);
        double sum = 0;
        for (auto [x, y] : onWall) sum += g.at(x, y);
        return sum / double(onWall.size());
    };
    // Unreal's: the SH, the same at every pixel (to the SH's float rounding).
    CHECK(meanOnWall(s, 0) == doctest::Approx(0.6).epsilon(2e-3));
    // Traced: each pixel averages 64 Bernoulli(½)·0.6 samples (σ 0.0375), the mean over the
    // pixels ≥ 60 of them σ ≤ 0.005: within 4σ.
    for (int bounces : {1, 3}) {
        CAPTURE(bounces);
        CHECK(std::abs(meanOnWall(s, bounces) - 0.3) < 0.02);
    }
    Scene closed = s;
    const Vec3d X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
    const double h = 2e5;
    for (const auto& [centre, u, v] : {std::tuple{X * h, Y, Z}, {X * -h, Z, Y}, {Y * h, Z, X},
                                       {Y * -h, X, Z}, {Z * h, X, Y}, {Z * -h, Y, X}})
        closed.meshes.push_back(test::quad(centre, u, v, h, 2, 3));
    CHECK(meanOnWall(closed, 0) == doctest::Approx(0.6).epsilon(2e-3));
    CHECK(meanOnWall(closed, 1) == 0.0);
}

TEST_CASE("rt_reflections: a screen percentage traces the top-left pixel of each block") {
    // Texel (x, y) at 1/k resolution is the full-resolution pass's pixel (k·x, k·y), bit for bit,
    // Unreal's hybrid included (its hits are projected onto the frame, not onto the texels).
    Scene s;
    s.materials.push_back(test::mirror());
    s.materials[0].roughness = 0.3f;
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 1000.0, 0, 1));
    s.meshes.push_back(test::sphere({0, 8, 0}, 6.0, 24, 0, 2));
    s.lights.push_back(test::sun({0.3, -1, 0.2}));
    s.environment.sky.enabled = true;
    s.environment.sky.color = {0.25f, 0.5f, 1.0f};
    const int n = 17;
    auto src = test::captureToMemory(s, camera({0, 20, -40}, {0, 0, 0}, n, n, 40.0));
    for (bool hybrid : {false, true}) {
        const auto full = runRtr(src, {{"samplesPerPixel", 2}, {"hybrid", hybrid}});
        for (auto [percent, k] : {std::pair{50.0, 2}, {25.0, 4}}) {
            const auto part = runRtr(src, {{"samplesPerPixel", 2}, {"hybrid", hybrid},
                                           {"screenPercentage", percent}});
            for (const char* name : {"rt_reflections.reflection", "rt_reflections.hitDistance"}) {
                const Image& a = part.at(name).image();
                const Image& b = full.at(name).image();
                REQUIRE(a.width() == (n + k - 1) / k);
                for (int c = 0; c < a.channelCount(); ++c)
                    for (int y = 0; y < a.height(); ++y)
                        for (int x = 0; x < a.width(); ++x)
                            CHECK(a.plane(c).at(x, y) ==
                                  b.plane(c).at(std::min(k * x, n - 1), std::min(k * y, n - 1)));
            }
        }
    }
}

TEST_CASE("rt_reflections: a light's visible shape is reflected by its light, not as emission") {
    // A mirror floor under a glowing quad: as a plain emissive surface its emission is what the
    // mirror shows; marked as a light's shape (Mesh::shapeOf) it adds nothing, the light's own
    // specular (deferred_lighting) being its reflection. The light itself points away.
    Scene s;
    s.materials.push_back(test::mirror());
    s.materials.push_back(test::lambert(0.0f, 2.0f));
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 1000.0, 0, 1));
    s.meshes.push_back(test::quad({0, 30, 0}, {1, 0, 0}, {0, 0, 1}, 1000.0, 1, 2));  // faces down
    const FrameCamera cam = camera({0, 10, -5}, {0, 0, 5}, 16, 16, 40.0);
    auto plain = test::captureToMemory(s, cam);
    CHECK(runRtr(plain).at("rt_reflections.reflection").image().plane(0).at(8, 12) ==
          doctest::Approx(2.0f));
    Light l;
    l.name = "panel";
    l.type = LightType::Directional;
    l.direction = {0, 1, 0};  // shines upwards: lights nothing here
    s.lights.push_back(l);
    s.meshes[1].shapeOf = 0;
    auto shape = test::captureToMemory(s, cam);
    CHECK(runRtr(shape).at("rt_reflections.reflection").image().plane(0).at(8, 12) == 0.0f);
}

}  // namespace fp

namespace fp {

TEST_CASE("rt_reflections: the hybrid takes the lit colour where a hit lands on screen") {
    // The mirror floor and the spot-lit wall of the first case, the wall on screen. With the
    // hybrid a floor pixel whose ray meets the wall where the screen shows it reflects the
    // capture's SceneColor of that wall pixel, bit for bit; shaded, its value is the wall's
    // radiance at the hit, which matches no pixel's stored colour exactly.
    Scene s;
    s.materials.push_back(test::mirror());
    s.materials.push_back(test::lambert(0.6f));
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 100.0, 0, 1));
    s.meshes.push_back(test::quad({0, 50, 60}, {1, 0, 0}, {0, 1, 0}, 50.0, 1, 2));
    Light l;
    l.name = "spot";
    l.type = LightType::Spot;
    l.position = {10, 40, 20};
    l.direction = {0, 0, 1};
    l.innerConeDegrees = 30.0f;
    l.outerConeDegrees = 35.0f;
    l.intensity = 5000.0f;
    s.lights.push_back(l);
    auto src = test::captureToMemory(s, camera({0, 20, -40}, {0, 25, 30}, 32, 32, 70.0));
    const Plane& color = src.buffers.at("SceneColor").plane(1);
    const Plane& instance = src.buffers.at("InstanceId").plane(0);
    std::set<float> wallColours;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            if (instance.at(x, y) == 2.0f) wallColours.insert(color.at(x, y));
    REQUIRE(wallColours.size() > 50);
    auto reused = [&](const std::map<std::string, Texture>& out) {
        const Plane& r = out.at("rt_reflections.reflection").image().plane(1);
        int floor = 0, found = 0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                if (instance.at(x, y) != 1.0f || r.at(x, y) == 0.0f) continue;
                ++floor;
                found += wallColours.count(r.at(x, y)) > 0;
            }
        return std::make_pair(floor, found);
    };
    const auto [floorPlain, foundPlain] = reused(runRtr(src));
    const auto [floorHybrid, foundHybrid] = reused(runRtr(src, {{"hybrid", true}}));
    CHECK(floorPlain > 50);
    CHECK(foundPlain <= floorPlain / 20);
    CHECK(foundHybrid >= floorHybrid / 2);
}

TEST_CASE("rt_reflections: rays traced in waves give the bits of one ray at a time") {
    // A glossy floor under a mirror sphere and a rough glowing one, a sun with a source angle, a
    // soft point light, a spot and a rect light, the sky on: mirror and GGX rays, hits lit by
    // every kind of light sample (blocked by the spheres or not, behind the rect light or outside
    // the spot's cone or not), misses that see the sky, beside each other in the same packets and
    // lanes (ShadingTests checks the lanes' samples of a light with extent, several a light).
    // 70 pixels leave a partial tile.
    Scene scene;
    Material glossy;
    glossy.baseColor = {0.6f, 0.5f, 0.4f};
    glossy.metallic = 0.5f;
    glossy.roughness = 0.3f;
    scene.materials.push_back(glossy);
    scene.materials.push_back(test::mirror());
    Material rough = test::lambert(0.5f, 0.2f);
    rough.specular = 0.5f;
    rough.roughness = 0.5f;
    scene.materials.push_back(rough);
    scene.sceneUnitsPerMeter = 100.0;
    scene.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 100.0, 0, 1));
    scene.meshes.push_back(test::sphere({-12, 10, 0}, 9.0, 32, 1, 2));
    scene.meshes.push_back(test::sphere({12, 10, 5}, 9.0, 32, 2, 3));
    scene.lights.push_back(test::sun({0.3, -1, 0.2}, 2.0f));
    scene.lights.push_back(test::spotLight({10, 40, -10}, {0, -1, 0.3}, 10.0f, 30.0f, 1.0f, 800.0f));
    scene.lights.push_back(test::pointLight({15, 30, -15}, 2.0f, 400.0f));
    scene.lights.push_back(test::rectLight({-20, 25, -10}, {5, 0, 0}, {0, 0, 5}, 50.0f));
    scene.environment.sky.enabled = true;
    const int n = 70;
    auto src = test::captureToMemory(scene, camera({0, 25, -50}, {0, 5, 10}, n, n, 60.0));
    const std::vector<std::string> outputs = {"rt_reflections.reflection",
                                              "rt_reflections.hitDistance"};
    for (const nlohmann::json& params :
         {nlohmann::json{{"samplesPerPixel", 3}, {"maxRoughness", 1.0}},
          nlohmann::json{{"samplesPerPixel", 2}, {"shadows", 0}},
          nlohmann::json{{"hitIndirectBounces", 2}},
          nlohmann::json{{"hybrid", true}, {"samplesPerPixel", 2}},
          nlohmann::json{{"screenPercentage", 50.0}}}) {
        CAPTURE(params.dump());
        nlohmann::json one = params;
        one["waves"] = false;
        const auto single = test::runChain(src, {test::node("rt_reflections", one)}, outputs);
        // The waves' rays and light samples run in SIMD lanes: on every instruction set the
        // CPU has.
        test::onEveryLaneTarget([&] {
            const auto waves = test::runChain(src, {test::node("rt_reflections", params)}, outputs);
            // Not vacuous: hits lit and misses that saw the sky, in the same frame.
            const Plane& distance = waves.at("rt_reflections.hitDistance").image().plane(0);
            const Plane& red = waves.at("rt_reflections.reflection").image().plane(0);
            int hits = 0, sky = 0, lit = 0;
            for (int y = 0; y < distance.height(); ++y)
                for (int x = 0; x < distance.width(); ++x) {
                    hits += distance.at(x, y) > 0.0f && distance.at(x, y) < 1e19f;
                    sky += distance.at(x, y) == 1e20f;
                    lit += red.at(x, y) > 0.0f;
                }
            const int texels = distance.width() * distance.height();
            CHECK(hits > texels / 10);
            CHECK(sky > texels / 20);
            CHECK(lit > texels / 2);
            for (const std::string& name : outputs)
                for (int c = 0; c < waves.at(name).image().channelCount(); ++c)
                    CHECK(test::sameBits(waves.at(name).image().plane(c),
                                         single.at(name).image().plane(c)));
        });
    }
}

TEST_CASE("rt_reflections: on the hard capture the BVH path lights its hits as Embree's") {
    // The hard scene (a grazing floor, a mirror and a rough sphere, a 1 cm pole, 10⁷ units from
    // the origin) at its own camera: where both traversals find the same hit (the same distance
    // to a few float steps), the bulb's shadow ray from it must decide alike. A hit point taken as
    // org + t·dir from the watertight test's distance lay up to ~10⁻⁵ behind the surface along
    // grazing rays and shadowed itself (32 of 65,536 pixels black at 256², the reflections' RMSE
    // against the truth 0.0335 against Embree's 0.0317).
    io::SceneFile sf = io::loadScene(std::string(FP_SOURCE_DIR) + "/examples/hard/scene.json");
    auto src = test::captureToMemory(sf.scene, sf.cameraForFrame(1, {256, 256}));
    const std::vector<std::string> outputs = {"rt_reflections.reflection", "rt_reflections.hitDistance"};
    const auto embree = test::runChain(src, {test::node("rt_reflections")}, outputs);
    const auto bvh = test::runChain(src, {test::node("rt_reflections", {{"traversal", "bvh"}})}, outputs);
    const Image& re = embree.at(outputs[0]).image();
    const Image& rb = bvh.at(outputs[0]).image();
    const Plane& he = embree.at(outputs[1]).image().plane(0);
    const Plane& hb = bvh.at(outputs[1]).image().plane(0);
    int sameHit = 0, lightDiffers = 0;
    for (int y = 0; y < re.height(); ++y)
        for (int x = 0; x < re.width(); ++x) {
            const double a = he.at(x, y), b = hb.at(x, y);
            if (!(a > 0.0) || a >= 1e19 || std::fabs(a - b) > 1e-4 * a) continue;
            ++sameHit;
            const double ea = re.plane(0).at(x, y), eb = rb.plane(0).at(x, y);
            lightDiffers += std::fabs(ea - eb) > 1e-3 * std::max(std::fabs(ea), 1e-6);
        }
    MESSAGE("pixels with the same hit " << sameHit << ", lit otherwise at " << lightDiffers);
    CHECK(sameHit > 1000);  // the spheres and the pole in the floor's reflection
    // Only a shadow ray passing within a few float steps of an edge may decide otherwise.
    CHECK(lightDiffers * 10000 <= sameHit);
}

}  // namespace fp
