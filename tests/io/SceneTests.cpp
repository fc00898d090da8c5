#include "io/CameraIO.h"
#include "io/scene/SceneLoader.h"
#include "foundation/Error.h"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace fp;

TEST_SUITE("io") {

TEST_CASE("the Cornell OBJ loads with its published materials and a rect light") {
    const auto sf = io::loadScene(std::string(FP_SOURCE_DIR) + "/examples/cornell/scene.json");
    CHECK(sf.scene.meshes.size() == 8);  // floor, ceiling, 3 walls, light, 2 blocks
    CHECK(sf.scene.sceneUnitsPerMeter == 1000.0);
    REQUIRE(sf.scene.lights.size() == 1);
    CHECK(sf.scene.lights[0].type == LightType::Rect);
    bool red = false;
    for (const auto& m : sf.scene.materials)
        if (m.name == "red") {
            red = true;
            CHECK(m.baseColor.x == doctest::Approx(0.63f));
            CHECK(m.specular == 0.0f);  // override from scene.json
        }
    CHECK(red);
    const FrameCamera cam = sf.cameraForFrame(1, {64, 64});
    CHECK(cam.current.position.x == doctest::Approx(278.0));
    REQUIRE(cam.previous);
    CHECK(cam.previous->position.x == doctest::Approx(248.0));  // cameraMotion 30 mm per frame
    CHECK(sf.cameraForFrame(3, {64, 64}).previous->position.x == doctest::Approx(308.0));
}

TEST_CASE("the hard-case glTF loads meshes, its camera and KHR_lights_punctual, offset by 10^7") {
    const auto sf = io::loadScene(std::string(FP_SOURCE_DIR) + "/examples/hard/scene.json");
    CHECK(sf.scene.meshes.size() == 4);
    REQUIRE(sf.scene.lights.size() == 2);
    CHECK(sf.scene.lights[0].type == LightType::Directional);  // glTF sun
    CHECK(sf.scene.lights[0].direction.y < 0.0);                // shines downwards
    CHECK(sf.scene.lights[1].position.x == doctest::Approx(1e7));
    const FrameCamera cam = sf.cameraForFrame(1, {64, 64});
    CHECK(cam.current.position.x == doctest::Approx(1e7));
    CHECK(cam.current.position.y == doctest::Approx(20.0));
    CHECK(cam.current.forward.z == doctest::Approx(1.0));  // glTF −Z turned to +Z by the node
    CHECK(cam.current.nearPlane == doctest::Approx(10.0));
}

TEST_CASE("a sidecar camera with OpenGL axes equals the same look-at camera") {
    const CameraView ref = CameraView::lookAt({1, 2, 3}, {1, 2, 13}, {0, 1, 0}, 50.0, 80, 60, 5.0);
    // OpenGL camera-to-world: columns right, up, −forward, position.
    const nlohmann::json j = {
        {"cameraToWorld", {ref.right.x, ref.up.x, -ref.forward.x, 1.0, ref.right.y, ref.up.y,
                           -ref.forward.y, 2.0, ref.right.z, ref.up.z, -ref.forward.z, 3.0, 0, 0, 0, 1}},
        {"axes", "opengl"}, {"fovYDegrees", 50.0}, {"near", 5.0}};
    const CameraView c = io::cameraViewFromJson(j, {80, 60}, "test");
    CHECK(length(c.forward - ref.forward) < 1e-12);
    CHECK(length(c.right - ref.right) < 1e-12);
    CHECK(c.fx == doctest::Approx(ref.fx));
    CHECK_THROWS_AS(io::cameraViewFromJson({{"axes", "opengl"}}, {8, 8}, "x"), UsageError);
}

TEST_CASE("a scene with a bad key or a degenerate index is a clear error") {
    const std::string dir = std::string(FP_TEST_SCRATCH) + "/scenes";
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/bad.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    std::ofstream(dir + "/bad.json") << R"({"version": 1, "geometry": "bad.obj"})";
    CHECK_THROWS_WITH_AS(io::loadScene(dir + "/bad.json"), doctest::Contains("bad.obj"), Error);
    std::ofstream(dir + "/typo.json") << R"({"version": 1, "geometry": "bad.obj", "lihgts": []})";
    CHECK_THROWS_WITH_AS(io::loadScene(dir + "/typo.json"), doctest::Contains("did you mean 'lights'?"),
                         Error);
}

}

TEST_SUITE("io") {

TEST_CASE("an OBJ without normals is smoothed by angle where the scene asks") {
    // Two triangles folded 90° along the edge x = 0 (the floor z = 0 and the wall x = 0): the
    // shared vertices' normal is (√½, 0, √½) under a 100° limit and stays each face's own under
    // a 30° one (a hard edge); with no "smoothAngleDegrees" the mesh has no normals (faceted).
    const std::string dir = std::string(FP_TEST_SCRATCH) + "/scenes";
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/fold.obj") << "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n";
    auto load = [&](const std::string& extra) {
        std::ofstream(dir + "/fold.json")
            << R"({"version": 1, "geometry": "fold.obj")" << extra << "}";
        auto sf = io::loadScene(dir + "/fold.json");
        REQUIRE(sf.scene.meshes.size() == 1);
        return sf.scene.meshes[0];
    };
    CHECK(load("").normals.empty());
    const Mesh soft = load(R"(, "smoothAngleDegrees": 100)");
    REQUIRE(soft.normals.size() == 6);
    const float h = float(std::sqrt(0.5));
    CHECK(soft.normals[0].x == doctest::Approx(h));  // vertex 1 of the floor, on the edge
    CHECK(soft.normals[0].z == doctest::Approx(h));
    CHECK(soft.normals[1].z == doctest::Approx(1.0f));  // vertex 3, the floor's alone
    const Mesh hard = load(R"(, "smoothAngleDegrees": 30)");
    CHECK(hard.normals[0].z == doctest::Approx(1.0f));
    CHECK(hard.normals[3].x == doctest::Approx(1.0f));  // the wall's own normal
    CHECK_THROWS_WITH_AS(load(R"(, "smoothAngleDegrees": 200)"),
                         doctest::Contains("/smoothAngleDegrees"), Error);
}

TEST_CASE("an OBJ scene's lights are read without its meshes; the meshes when asked, once") {
    auto sf = io::loadScene(std::string(FP_SOURCE_DIR) + "/examples/cornell/scene.json",
                            io::SceneParts::LightsAndCameras);
    CHECK_FALSE(sf.hasGeometry());
    CHECK(sf.scene.meshes.empty());
    REQUIRE(sf.scene.lights.size() == 1);
    CHECK(sf.scene.lights[0].name == "ceiling");
    sf.loadGeometry();
    CHECK(sf.hasGeometry());
    CHECK(sf.scene.meshes.size() == 8);
    sf.loadGeometry();  // a second call reads nothing more
    CHECK(sf.scene.meshes.size() == 8);
    REQUIRE(sf.scene.lights.size() == 1);
    const auto whole = io::loadScene(std::string(FP_SOURCE_DIR) + "/examples/cornell/scene.json");
    CHECK(whole.scene.lights[0].position.y == sf.scene.lights[0].position.y);
    // The light's "shape" marks the light quad, whichever way the geometry was read.
    for (const Scene* s : std::initializer_list<const Scene*>{&sf.scene, &whole.scene}) {
        int shapes = 0;
        for (const auto& m : s->meshes) {
            CHECK(m.shapeOf == (m.name == "light" ? 0 : -1));
            shapes += m.shapeOf == 0 ? 1 : 0;
        }
        CHECK(shapes == 1);
    }
}

TEST_CASE("a light's shape must name a mesh, and a mesh can be the shape of one light only") {
    const std::string dir = std::string(FP_TEST_SCRATCH) + "/scenes";
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/two.obj") << "o lamp\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
                                       "o floor\nv 0 0 0\nv 0 0 1\nv 1 0 0\nf 4 5 6\n";
    std::ofstream(dir + "/typo_shape.json")
        << R"({"version": 1, "geometry": "two.obj", "lights": [{"type": "point", "shape": "lmap"}]})";
    CHECK_THROWS_WITH_AS(io::loadScene(dir + "/typo_shape.json"),
                         doctest::Contains("/lights/0/shape: no mesh named 'lmap'"), Error);
    CHECK_THROWS_WITH_AS(io::loadScene(dir + "/typo_shape.json"), doctest::Contains("did you mean 'lamp'?"),
                         Error);
    std::ofstream(dir + "/twice.json") << R"({"version": 1, "geometry": "two.obj", "lights": [
        {"name": "a", "shape": "lamp"}, {"name": "b", "shape": "lamp"}]})";
    CHECK_THROWS_WITH_AS(io::loadScene(dir + "/twice.json"),
                         doctest::Contains("/lights/1/shape: mesh 'lamp' is already the shape of light 'a'"),
                         Error);
    std::ofstream(dir + "/number.json")
        << R"({"version": 1, "geometry": "two.obj", "lights": [{"shape": 3}]})";
    CHECK_THROWS_WITH_AS(io::loadScene(dir + "/number.json"), doctest::Contains("/lights/0/shape"), Error);
    const auto ok = io::loadScene(dir + "/twice.json", io::SceneParts::LightsAndCameras);
    CHECK(ok.scene.meshes.empty());  // not checked until the meshes are read
}

TEST_CASE("a glTF scene keeps its own lights before the scene JSON's, offset with the scene") {
    const auto sf = io::loadScene(std::string(FP_SOURCE_DIR) + "/examples/hard/scene.json",
                                  io::SceneParts::LightsAndCameras);
    CHECK(sf.hasGeometry());  // its lights live in the glTF
    REQUIRE(sf.scene.lights.size() == 2);
    CHECK(sf.scene.lights[0].name == "sun");
    CHECK(sf.scene.lights[1].name == "bulb");
    CHECK(sf.scene.lights[1].position.x == doctest::Approx(1e7));
}

}
