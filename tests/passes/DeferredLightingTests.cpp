// deferred_lighting's rect-light integral in SIMD lanes against its scalar reference.
#include "passes/common/Lanes.h"
#include "passes/core/ShadingModel.h"
#include "passes/deferred_lighting/DeferredLightingLanes.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>

namespace fp {

namespace {

// A floor of four default-lit tiles (rough, glossy, metallic, mirror-like) with a clear-coat sphere and
// a cloth sphere on it, under a vertical rect light standing on the floor: the floor behind the
// emitter gets no light, the floor beside its plane gets part of the grid, the spheres go through
// the scalar BxDFs. Seen from above at an angle, 61 × 47 pixels (no multiple of any vector).
Scene mixedRoom() {
    Scene s;
    s.sceneUnitsPerMeter = 100.0;
    const float roughness[] = {0.9f, 0.5f, 0.2f, 0.0f};
    for (int i = 0; i < 4; ++i) {
        Material m;
        m.baseColor = {0.3f + 0.15f * i, 0.5f, 0.7f - 0.1f * i};
        m.roughness = roughness[i];
        m.metallic = i == 2 ? 1.0f : 0.0f;
        m.specular = 0.25f * float(i + 1);
        s.materials.push_back(m);
        s.meshes.push_back(
            test::quad({i % 2 ? 50.0 : -50.0, 0, i / 2 ? 50.0 : -50.0}, {1, 0, 0}, {0, 0, -1}, 50.0, i));
    }
    Material coat;
    coat.shadingModel = kClearCoat;
    coat.clearCoat = 1.0f;
    s.materials.push_back(coat);
    s.meshes.push_back(test::sphere({-30, 15, 0}, 15.0, 48, 4, 2));
    Material cloth;
    cloth.shadingModel = kCloth;
    cloth.opacity = 0.5f;
    s.materials.push_back(cloth);
    s.meshes.push_back(test::sphere({40, 12, 10}, 12.0, 48, 5, 3));
    Light l;
    l.name = "panel";
    l.type = LightType::Rect;
    l.position = {-20, 40, -20};
    l.halfU = {0, 0, 20};  // emits along halfU × halfV = +x
    l.halfV = {0, 20, 0};
    l.intensity = 5.0f;
    l.color = {1.0f, 0.9f, 0.8f};
    s.lights.push_back(l);
    return s;
}

FrameCamera angledCamera() {
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 180, 160}, {0, 0, 0}, {0, 1, 0}, 50.0, 61, 47, 10.0);
    cam.previous = cam.current;
    return cam;
}

}  // namespace

TEST_CASE("rect light in SIMD lanes gives the scalar reference's bits") {
    const Scene scene = mixedRoom();
    auto src = test::captureToMemory(scene, angledCamera());
    const std::vector<int64_t> targets = laneTargetsHere();
    REQUIRE(!targets.empty());
    int compared = 0;
    for (int64_t target : targets)
        for (int grid : {1, 3, 4, 5})
            for (bool shadowed : {false, true}) {
                std::vector<NodeDesc> lanes, scalar;
                for (bool inLanes : {true, false}) {
                    auto& nodes = inLanes ? lanes : scalar;
                    std::map<std::string, std::string> inputs = {{"color", "capture:Emissive"}};
                    if (shadowed) {
                        nodes.push_back(test::node("rt_shadows"));
                        inputs["attenuation"] = "rt_shadows.lightAttenuation";
                    }
                    nodes.push_back(test::node("deferred_lighting",
                                               {{"rectSamples", grid}, {"lanes", inLanes}}, inputs));
                }
                test::MemorySink a, b;
                useOnlyLaneTarget(target);
                INFO("lanes of ", deferred::lanes(), " floats, grid ", grid, ", shadowed ",
                     shadowed);
                const FrameReport ra =
                    executePlan(test::planFor(lanes, {"deferred_lighting.color"}), src, a);
                useOnlyLaneTarget(0);
                const FrameReport rb =
                    executePlan(test::planFor(scalar, {"deferred_lighting.color"}), src, b);
                CHECK(ra.passes.back().work == rb.passes.back().work);
                // Some pixels are lit and some out of reach (behind the emitter), so both branches
                // are compared.
                CHECK(ra.passes.back().work.at("pixels") > 500);
                CHECK(ra.passes.back().work.at("skippedPixels") > 200);
                const Image& la = a.layers.at("deferred_lighting.color").image();
                const Image& lb = b.layers.at("deferred_lighting.color").image();
                for (int c = 0; c < 3; ++c)
                    CHECK(test::sameBits(la.plane(c), lb.plane(c)));
                ++compared;
            }
    CHECK(compared == 8 * int(targets.size()));
}

}  // namespace fp
