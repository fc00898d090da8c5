#include "app/SessionInputs.h"

#include "app/Invocation.h"
#include "io/CaptureSource.h"
#include "reference/ReflectionCaptureRenderer.h"

#include <algorithm>
#include "foundation/Error.h"

namespace fp::app {

io::SceneFile& SessionInputs::description() {
    if (!mScene) {
        if (mScenePath.empty())
            throw UsageError(fmt::format("{}: /scene: a pass needs the scene; name the scene JSON "
                                         "with \"scene\" (the capture records none)",
                                         mConfigPath));
        mScene = io::loadScene(mScenePath, io::SceneParts::LightsAndCameras);
        // Both sides say their units: the scene is brought into the capture's.
        if (mCaptureUnitsPerMeter && mScene->unitsDeclared &&
            mScene->scene.sceneUnitsPerMeter != *mCaptureUnitsPerMeter) {
            logInfo(fmt::format("{}: the scene is in {} units per metre and the capture in {}: "
                                "scaled by {}",
                                mScenePath, mScene->scene.sceneUnitsPerMeter,
                                *mCaptureUnitsPerMeter,
                                *mCaptureUnitsPerMeter / mScene->scene.sceneUnitsPerMeter));
            mScene->convertUnits(*mCaptureUnitsPerMeter);
        }
    }
    return *mScene;
}

const io::SceneFile& SessionInputs::scene() {
    io::SceneFile& sf = description();
    sf.loadGeometry();
    return sf;
}

std::shared_ptr<const RayScene> SessionInputs::rayScene(const Vec3d& origin) {
    const io::SceneFile& sf = scene();
    std::lock_guard<std::mutex> lock(mRaySceneMutex);
    const bool same = mRayScene && mRayScene->origin().x == origin.x &&
                      mRayScene->origin().y == origin.y && mRayScene->origin().z == origin.z;
    if (!same)
        mRayScene = std::make_shared<const RayScene>(sf.scene, origin);
    return mRayScene;
}

const std::vector<Light>& SessionInputs::lights() {
    return description().scene.lights;
}

const Environment& SessionInputs::environment() {
    io::SceneFile& sf = description();
    Environment& env = sf.scene.environment;
    // Captures the scene JSON gives no cubemap for are rendered from the scene, once.
    const bool toRender = std::any_of(env.captures.begin(), env.captures.end(),
                                      [](const ReflectionCapture& c) { return c.faces.width() == 0; });
    if (toRender) {
        sf.loadGeometry();
        renderMissingReflectionCaptures(sf.scene);
    }
    return env;
}

std::vector<std::pair<std::string, std::string>> SessionInputs::filesRead() const {
    std::vector<std::pair<std::string, std::string>> files;
    if (mScene) {
        files.emplace_back("scene", mScenePath);
        // A glTF is read whole with the lights; an OBJ's meshes only when a pass traces rays.
        if (mScene->hasGeometry())
            files.emplace_back("geometry", mScene->geometryFile());
    }
    if (mColorConfig)
        files.emplace_back("ocioConfig", io::colorConfigPath(mOcioPath));
    return files;
}

OCIO_NAMESPACE::ConstConfigRcPtr SessionInputs::colorConfig() {
    if (!mColorConfig)
        mColorConfig = io::loadColorConfig(mOcioPath);
    return mColorConfig;
}

}  // namespace fp::app
