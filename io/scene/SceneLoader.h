#pragma once
// Loads a framepass scene: a small JSON that names a geometry file (glTF 2.0 .gltf/.glb through
// tinygltf, or OBJ/MTL through tinyobjloader) and adds cameras, lights and material overrides.
// Everything is kept in double-precision world space; an "offset" moves the whole scene (geometry,
// lights, cameras), which is how the hard-case scene puts its camera 10⁷ units from the origin.
#include "foundation/Camera.h"
#include "foundation/Image.h"
#include "foundation/Scene.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace fp::io {

/// What loadScene reads: everything, or the lights and cameras only (an OBJ's meshes are then
/// read by SceneFile::loadGeometry when a pass needs them; a glTF is always read whole, since its
/// lights and camera live in it).
enum class SceneParts { LightsAndCameras, All };

class SceneFile {
public:
    Scene scene;
    Extent resolution{320, 240};  //!< "resolution" of the scene JSON, used when capture gets none
    std::string path;

    /// This frame's camera and the previous frame's: "camera" moved by "cameraMotion" per frame
    /// after frame 1; the previous camera is "previousCamera" when given, else frame − 1's.
    FrameCamera cameraForFrame(int64_t frame, Extent extent) const;

    nlohmann::json cameraJson, previousCameraJson;  //!< as written (or from the glTF camera)
    Vec3d cameraMotion;
    Vec3d offset;

    /// The scene JSON gives "sceneUnitsPerMeter" (otherwise 100 is assumed), and its value.
    bool unitsDeclared = false;
    double unitsAsWritten = 100.0;
    /// Rescales the scene into `targetUnitsPerMeter` (a capture's units): geometry (now or when
    /// it is read), lights (positions, extents, radii; point and spot intensities ×k², as their
    /// irradiance falls with distance in scene units) and reflection captures. The scene JSON's
    /// cameras are left as written: a run takes its camera from the capture.
    void convertUnits(double targetUnitsPerMeter);

    /// Reads the meshes (and materials) of the geometry file, once; `scene.meshes` is empty
    /// before. Throws fp::Error like loadScene.
    void loadGeometry();
    bool hasGeometry() const { return mGeometryLoaded; }
    /// The geometry file the scene JSON names (.gltf, .glb or .obj), resolved.
    const std::string& geometryFile() const { return mGeometryFile; }

private:
    friend SceneFile loadScene(const std::string& path, SceneParts parts);
    std::string mGeometryFile;
    nlohmann::json mMaterialOverrides;  //!< "materials" of the scene JSON, applied to the geometry
    std::size_t mJsonLightCount = 0;    //!< the last lights of scene.lights came from the JSON
    bool mGeometryLoaded = false;
    double mUnitScale = 1.0;  //!< convertUnits' factor, applied to geometry read after it
    std::optional<float> mSmoothAngleDegrees;  //!< "smoothAngleDegrees": OBJ normals smoothed
    /// Sets Mesh::shapeOf from each JSON light's "shape" once both are loaded.
    void markLightShapes();
};

/// Throws fp::Error naming the file (and the JSON pointer, mesh or accessor) on bad input.
SceneFile loadScene(const std::string& path, SceneParts parts = SceneParts::All);

/// A fingerprint of a scene as it is on disk: FNV-1a (64 bits, hex) over its JSON's bytes and
/// its geometry file's. A capture records it beside the scene's path, so a run that takes the
/// scene from the capture knows whether the file changed since.
std::string sceneFingerprint(const SceneFile& scene);

}  // namespace fp::io
