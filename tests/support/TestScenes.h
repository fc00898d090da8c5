#pragma once
// Small scenes and in-memory frame sources for tests: no files, exact geometry.
#include "reference/GBufferRenderer.h"
#include "framework/Executor.h"
#include "framework/Planner.h"
#include "foundation/RayScene.h"
#include "foundation/Scene.h"

#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <string>

namespace fp::test {

/// A square of side 2·half centred at `centre`, spanned by unit axes u and v (normal u × v).
inline Mesh quad(const Vec3d& centre, const Vec3d& u, const Vec3d& v, double half, int material = 0,
                 uint32_t instance = 1) {
    Mesh m;
    m.positions = {centre - u * half - v * half, centre + u * half - v * half,
                   centre + u * half + v * half, centre - u * half + v * half};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    m.instanceId = instance;
    return m;
}

/// A UV sphere of `segments` × segments/2 quads, outward-wound.
inline Mesh sphere(const Vec3d& centre, double radius, int segments, int material = 0,
                   uint32_t instance = 1) {
    Mesh m;
    const int rings = segments / 2;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            const double theta = kPi * r / rings, phi = 2.0 * kPi * s / segments;
            m.positions.push_back(centre + Vec3d{std::sin(theta) * std::cos(phi), std::cos(theta),
                                                 std::sin(theta) * std::sin(phi)} * radius);
        }
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = uint32_t(r * (segments + 1) + s), b = a + uint32_t(segments + 1);
            m.indices.insert(m.indices.end(), {a, a + 1, b, a + 1, b + 1, b});
        }
    m.material = material;
    m.instanceId = instance;
    return m;
}

/// A perfect mirror: a metal of base colour 1 (Schlick F = 1) and roughness 0.
inline Material mirror() {
    Material m;
    m.baseColor = {1, 1, 1};
    m.metallic = 1.0f;
    m.roughness = 0.0f;
    return m;
}

/// A pure Lambert material (no specular lobe) of grey albedo, optionally glowing.
inline Material lambert(float albedo, float emission = 0.0f) {
    Material m;
    m.baseColor = {albedo, albedo, albedo};
    m.specular = 0.0f;
    m.roughness = 1.0f;
    m.emission = {emission, emission, emission};
    return m;
}

/// A Lambert floor (y = 0, 200 units wide) lit by nothing.
inline Scene floorScene(const Vec3d& offset = {}) {
    Scene s;
    s.materials.push_back(lambert(0.5f));
    s.meshes.push_back(quad(offset, {1, 0, 0}, {0, 0, -1}, 100.0));
    return s;
}

/// Radiance of every surface of floorAndWall().
constexpr float kGlow = 0.1f;

/// A glowing black floor (y = 0) and a glowing black wall behind it (z = 30, facing the camera),
/// both wider and taller than wallCamera's view, so every pixel on screen has radiance exactly
/// kGlow and no sky is visible: whatever a screen-space ray reads, a hit gathers kGlow.
inline Scene floorAndWall() {
    Scene s;
    s.materials.push_back(lambert(0.0f, kGlow));
    s.meshes.push_back(quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 1000.0, 0, 1));
    s.meshes.push_back(quad({0, 0, 30}, {-1, 0, 0}, {0, 1, 0}, 1000.0, 0, 2));
    return s;
}

/// A still camera over floorAndWall()'s floor, looking at the wall.
inline FrameCamera wallCamera(int size) {
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 12, -20}, {0, 4, 20}, {0, 1, 0}, 60.0, size, size, 1.0);
    cam.previous = cam.current;
    return cam;
}

/// Form factor from floor point p (normal +y) to the part of floorAndWall()'s wall that is on
/// screen (what a screen-space tracer can hit), by midpoint quadrature over 0.25-unit cells, each
/// weighed by `weight(sx, sy)` of its screen position in [−1, 1]².
template <class Weight>
double onScreenWallFormFactor(const Vec3d& p, const CameraView& cam, Weight weight) {
    const double cell = 0.25;
    double f = 0.0;
    for (double y = 0.5 * cell; y < 60.0; y += cell)
        for (double x = -60.0 + 0.5 * cell; x < 60.0; x += cell) {
            const Vec3d q{x, y, 30.0};
            const auto proj = cam.project(q);
            if (proj.depth <= 0 || proj.px < 0 || proj.py < 0 || proj.px >= cam.width ||
                proj.py >= cam.height)
                continue;
            const Vec3d d = q - p;
            const double r2 = dot(d, d);
            f += d.y * d.z / (kPi * r2 * r2) * cell * cell *
                 weight(proj.px / cam.width * 2 - 1, 1 - proj.py / cam.height * 2);
        }
    return f;
}

/// Everything a pass can ask for, held in memory.
class MemorySource final : public FrameSource {
public:
    FrameInfo info;
    std::map<std::string, Image> buffers;
    const Scene* sceneData = nullptr;
    std::vector<std::string> loaded;  //!< buffers read, in order

    FrameInfo frameInfo() override { return info; }
    Texture loadBuffer(const std::string& buffer, int) override {
        loaded.push_back(buffer);
        return Texture(buffers.at(buffer));
    }
    const std::vector<Light>& lights() override { return sceneData->lights; }
    const Environment& environment() override { return sceneData->environment; }
    const RayScene& scene() override {
        if (!mRayScene) mRayScene = std::make_unique<RayScene>(*sceneData, info.camera.current.position);
        return *mRayScene;
    }
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() override;

private:
    std::unique_ptr<RayScene> mRayScene;
};

/// Keeps copies of everything written.
class MemorySink final : public FrameSink {
public:
    std::map<std::string, Texture> layers;  //!< layer name → texture
    void write(const OutputDesc&, const std::vector<OutputLayer>& ls, const FrameInfo&) override {
        for (const auto& l : ls) layers[l.name] = *l.texture;
    }
};

/// Captures a scene in memory with the real renderer.
inline MemorySource captureToMemory(const Scene& scene, const FrameCamera& cam, int64_t frame = 1) {
    MemorySource src;
    CaptureSettings settings;
    settings.frame = frame;
    settings.lightSamples = 4;
    src.buffers = GBufferRenderer(scene, cam, settings).render().buffers;
    src.info.number = frame;
    src.info.extent = {cam.current.width, cam.current.height};
    src.info.camera = cam;
    src.info.hasCamera = true;
    src.sceneData = &scene;
    return src;
}

/// A plan of the built-in passes `nodes` writing each of `outputs` ("pass.port") to its own file.
inline Plan planFor(std::vector<NodeDesc> nodes, std::vector<std::string> outputs,
                    nlohmann::json cvars = nlohmann::json::object()) {
    GraphDesc g;
    for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i].pointer = "/passes/" + std::to_string(i);
    g.nodes = nodes;
    g.cvars = cvars;
    for (const auto& o : outputs) g.outputs.push_back({o + ".exr", {o}, "/outputs", false});
    return makePlan(g, builtinPasses(), {});
}

/// A config node named after its pass type.
inline NodeDesc node(std::string type, nlohmann::json params = nlohmann::json::object(),
                     std::map<std::string, std::string> inputs = {}) {
    return {type, type, params, inputs, ""};
}

/// Runs the built-in passes `nodes` on `src` and keeps `outputs` ("pass.port"); with `history`,
/// as a frame of a sequence.
inline std::map<std::string, Texture> runChain(MemorySource& src, const std::vector<NodeDesc>& nodes,
                                               const std::vector<std::string>& outputs,
                                               HistoryStore* history = nullptr) {
    MemorySink sink;
    executePlan(planFor(nodes, outputs), src, sink, {}, history);
    return sink.layers;
}

// A floor (y = 0) under a sphere of radius 10 centred at height 30, seen from straight above, so
// floor pixels map linearly to floor positions.
inline constexpr double kSphereRadius = 10.0;
inline Scene sphereOverFloor(const Vec3d& offset, Light light) {
    Scene s = floorScene(offset);
    s.sceneUnitsPerMeter = 100.0;
    s.meshes.push_back(sphere(offset + Vec3d{0, 30, 0}, kSphereRadius, 256, 0, 2));
    light.position += offset;
    s.lights.push_back(light);
    return s;
}

inline FrameCamera topCamera(const Vec3d& offset, int size) {
    FrameCamera cam;
    cam.current =
        CameraView::lookAt(offset + Vec3d{0, 200, 0}, offset, {0, 0, 1}, 20.0, size, size, 10.0);
    cam.previous = cam.current;
    return cam;
}

inline Light sun(const Vec3d& direction, float angleDegrees = 0.0f) {
    Light l;
    l.name = "sun";
    l.type = LightType::Directional;
    l.direction = normalize(direction);
    l.sourceAngleDegrees = angleDegrees;
    return l;
}
/// A point light of `radius` (a sphere: soft shadows) and radiant intensity `intensity`.
inline Light pointLight(const Vec3d& position, float radius, float intensity) {
    Light l;
    l.type = LightType::Point;
    l.position = position;
    l.radius = radius;
    l.intensity = intensity;
    return l;
}

/// A spot light at `position` along `direction`, its cone's half angles in degrees.
inline Light spotLight(const Vec3d& position, const Vec3d& direction, float innerDegrees,
                       float outerDegrees, float radius, float intensity) {
    Light l = pointLight(position, radius, intensity);
    l.type = LightType::Spot;
    l.direction = normalize(direction);
    l.innerConeDegrees = innerDegrees;
    l.outerConeDegrees = outerDegrees;
    return l;
}

/// A rect light centred at `position`, its half-extent axes `halfU`, `halfV` (emitting along
/// halfU × halfV), of radiance `intensity`.
inline Light rectLight(const Vec3d& position, const Vec3d& halfU, const Vec3d& halfV,
                       float intensity) {
    Light l;
    l.type = LightType::Rect;
    l.position = position;
    l.halfU = halfU;
    l.halfV = halfV;
    l.intensity = intensity;
    return l;
}

/// True when two planes hold the same bits in every pixel.
inline bool sameBits(const Plane& a, const Plane& b) {
    if (a.width() != b.width() || a.height() != b.height()) return false;
    for (int y = 0; y < a.height(); ++y)
        if (std::memcmp(a.row(y), b.row(y), sizeof(float) * a.width()) != 0) return false;
    return true;
}

}  // namespace fp::test
