#include "cli/SessionInputs.h"

#include "io/CaptureSource.h"
#include "passes/core/Error.h"

namespace fp::cli {

const io::SceneFile& SessionInputs::scene() {
    if (!mScene) {
        if (mScenePath.empty())
            throw UsageError(fmt::format("{}: /scene: a pass needs geometry; name the scene JSON",
                                         mConfigPath));
        mScene = io::loadScene(mScenePath);
    }
    return *mScene;
}

OCIO_NAMESPACE::ConstConfigRcPtr SessionInputs::colorConfig() {
    if (!mColorConfig) mColorConfig = io::loadColorConfig(mOcioPath);
    return mColorConfig;
}

}  // namespace fp::cli
