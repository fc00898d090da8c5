// deferred_lighting: default-lit pixels in SIMD lanes against the scalar reference, and a point
// light on a Lambert plane against I·cosθ/r² × albedo/π.
#include "screenspace/Lanes.h"
#include "foundation/ShadingModel.h"
#include "passes/deferred_lighting/DeferredLightingLanes.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace fp {

namespace {

// A floor of four default-lit tiles (rough, glossy, metallic, mirror-like) with a clear-coat sphere and
// a cloth sphere on it (they go through the scalar BxDFs), lit by `light`. Seen from above at an
// angle, 61 × 47 pixels (no multiple of any vector).
Scene mixedRoom(const Light& light) {
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
    s.lights.push_back(light);
    return s;
}

// A vertical rect light standing on the floor: the floor behind the emitter gets no light, the
// floor beside its plane part of the grid.
Light panel() {
    Light l;
    l.name = "panel";
    l.type = LightType::Rect;
    l.position = {-20, 40, -20};
    l.halfU = {0, 0, 20};  // emits along halfU × halfV = +x
    l.halfV = {0, 20, 0};
    l.intensity = 5.0f;
    l.color = {1.0f, 0.9f, 0.8f};
    return l;
}

// The lit colour with the lanes on (on one instruction set) and off, and the pass's work.
struct LanesAndScalar {
    Image lanes, scalar;
    std::map<std::string, uint64_t> lanesWork, scalarWork;
};

LanesAndScalar lanesAndScalar(test::MemorySource& src, int64_t target, int grid, bool shadowed) {
    LanesAndScalar r;
    for (bool inLanes : {true, false}) {
        std::vector<NodeDesc> nodes;
        std::map<std::string, std::string> inputs = {{"color", "capture:Emissive"}};
        if (shadowed) {
            nodes.push_back(test::node("rt_shadows"));
            inputs["attenuation"] = "rt_shadows.lightAttenuation";
        }
        nodes.push_back(
            test::node("deferred_lighting", {{"rectSamples", grid}, {"lanes", inLanes}}, inputs));
        test::MemorySink sink;
        useOnlyLaneTarget(inLanes ? target : 0);
        const FrameReport report =
            executePlan(test::planFor(nodes, {"deferred_lighting.color"}), src, sink);
        (inLanes ? r.lanes : r.scalar) = sink.layers.at("deferred_lighting.color").image();
        (inLanes ? r.lanesWork : r.scalarWork) = report.passes.back().work;
    }
    useOnlyLaneTarget(0);
    return r;
}

bool sameBits(const Image& a, const Image& b) {
    for (int c = 0; c < 3; ++c)
        if (!test::sameBits(a.plane(c), b.plane(c)))
            return false;
    return true;
}

FrameCamera angledCamera() {
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 180, 160}, {0, 0, 0}, {0, 1, 0}, 50.0, 61, 47, 10.0);
    cam.previous = cam.current;
    return cam;
}

}  // namespace

TEST_CASE("rect light in SIMD lanes gives the scalar reference's bits") {
    const Scene scene = mixedRoom(panel());
    auto src = test::captureToMemory(scene, angledCamera());
    const std::vector<int64_t> targets = laneTargetsHere();
    REQUIRE(!targets.empty());
    int compared = 0;
    for (int64_t target : targets)
        for (int grid : {1, 3, 4, 5})
            for (bool shadowed : {false, true}) {
                const LanesAndScalar r = lanesAndScalar(src, target, grid, shadowed);
                INFO("target ", target, ", grid ", grid, ", shadowed ", shadowed);
                CHECK(r.lanesWork == r.scalarWork);
                // Some pixels are lit and some out of reach (behind the emitter), so both branches
                // are compared.
                CHECK(r.lanesWork.at("pixels") > 500);
                CHECK(r.lanesWork.at("skippedPixels") > 200);
                CHECK(sameBits(r.lanes, r.scalar));
                ++compared;
            }
    CHECK(compared == 8 * int(targets.size()));
}

TEST_CASE("deferred lighting of a point light on a Lambert plane is I·cosθ/r² × albedo/π") {
    Scene s = test::floorScene();
    Light l;
    l.name = "bulb";
    l.position = {10, 40, 5};
    l.intensity = 3000.0f;
    l.color = {1.0f, 0.5f, 0.25f};
    s.lights.push_back(l);
    const FrameCamera cam = test::topCamera({}, 48);
    auto src = test::captureToMemory(s, cam);
    // Start from the base pass's colour (no emission: zero), unshadowed (nothing can occlude).
    const auto out =
        test::runChain(src, {test::node("deferred_lighting", {}, {{"color", "capture:Emissive"}})},
            {"deferred_lighting.color"});
    const Image& c = out.at("deferred_lighting.color").image();
    const Plane& depth = src.buffers.at("SceneDepth").plane(0);
    for (int y = 0; y < 48; y += 3)
        for (int x = 0; x < 48; x += 3) {
            const Vec3d p = cam.current.worldFromPixel(x, y, depth.at(x, y));
            const Vec3d d = l.position - p;
            const double r2 = dot(d, d), cosT = d.y / std::sqrt(r2);
            for (int ch = 0; ch < 3; ++ch) {
                const double expected = l.intensity * l.color[ch] * cosT / r2 * 0.5 / kPi;
                // Float positions and normals: 1e-4 relative.
                CHECK(c.plane(ch).at(x, y) == doctest::Approx(expected).epsilon(1e-4));
            }
        }
}

}  // namespace fp
