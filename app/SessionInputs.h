#pragma once
// The inputs a session shares across frames (and bench across settings): the scene file and the
// OCIO config, each read once on first use and only if something asks for it. The scene's lights
// (which the light templates and the lighting passes read) come without its meshes; the meshes
// are read only when a live pass traces rays.
#include "io/ConfigLoader.h"
#include "io/scene/SceneLoader.h"

#include <OpenColorIO/OpenColorIO.h>

#include "foundation/RayScene.h"

#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace fp::app {

class SessionInputs {
public:
    /// `configPath` names the config in errors; `config` gives the scene and OCIO paths.
    SessionInputs(std::string configPath, const io::RunConfig& config)
        : mConfigPath(std::move(configPath)),
          mScenePath(config.scene),
          mOcioPath(config.ocioConfig) {}

    bool hasScene() const { return !mScenePath.empty(); }
    /// The scene JSON, read once (its lights and cameras; an OBJ's meshes only when scene()
    /// asks). Throws fp::UsageError when the config names no scene.
    io::SceneFile& description();
    /// The capture's units, when its profile or header says them: a scene JSON that declares
    /// other units is converted into these when read. Call before the scene is first read.
    void setCaptureUnitsPerMeter(std::optional<double> units) { mCaptureUnitsPerMeter = units; }
    std::optional<double> captureUnitsPerMeter() const { return mCaptureUnitsPerMeter; }
    /// The scene with its geometry. Throws fp::UsageError when the config names no scene.
    const io::SceneFile& scene();
    /// The scene's lights, in order; the geometry is not read for them unless it holds them.
    const std::vector<Light>& lights();
    /// The scene's sky light and reflection captures, read with its lights; captures without a
    /// cubemap file are rendered from the scene's geometry on the first call.
    const Environment& environment();
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig();
    /// The scene's ray-traceable form around `origin` (a frame's camera position): the last one
    /// made is kept, so frames and re-runs from the same camera share one Embree BVH and one
    /// framepass BVH — built once, copied to the GPU once — where each frame's source would
    /// build its own. Another origin builds another (its coordinates are relative to it).
    std::shared_ptr<const RayScene> rayScene(const Vec3d& origin);
    /// The files read so far, as (role, path): "scene", "geometry", "ocioConfig".
    std::vector<std::pair<std::string, std::string>> filesRead() const;

private:
    std::string mConfigPath, mScenePath, mOcioPath;
    std::optional<io::SceneFile> mScene;
    std::optional<double> mCaptureUnitsPerMeter;
    std::mutex mRaySceneMutex;
    std::shared_ptr<const RayScene> mRayScene;  // the last made, around mRayScene->origin()
    OCIO_NAMESPACE::ConstConfigRcPtr mColorConfig;
};

}  // namespace fp::app
