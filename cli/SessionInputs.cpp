#include "cli/SessionInputs.h"

#include "io/CaptureSource.h"
#include "passes/core/Error.h"

namespace fp::cli {

io::SceneFile& SessionInputs::description() {
    if (!mScene) {
        if (mScenePath.empty())
            throw UsageError(fmt::format("{}: /scene: a pass needs the scene; name the scene JSON",
                                         mConfigPath));
        mScene = io::loadScene(mScenePath, io::SceneParts::LightsAndCameras);
    }
    return *mScene;
}

const io::SceneFile& SessionInputs::scene() {
    io::SceneFile& sf = description();
    sf.loadGeometry();
    return sf;
}

const std::vector<Light>& SessionInputs::lights() {
    return description().scene.lights;
}

OCIO_NAMESPACE::ConstConfigRcPtr SessionInputs::colorConfig() {
    if (!mColorConfig)
        mColorConfig = io::loadColorConfig(mOcioPath);
    return mColorConfig;
}

}  // namespace fp::cli
