#pragma once
// The inputs a run shares across frames (and bench across settings): the scene file and the OCIO
// config, each parsed once on first use and only if a live pass asks for it.
#include "io/ConfigLoader.h"
#include "io/SceneLoader.h"

#include <OpenColorIO/OpenColorIO.h>

#include <optional>
#include <string>

namespace fp::cli {

class SessionInputs {
public:
    /// `configPath` names the config in errors; `config` gives the scene and OCIO paths.
    SessionInputs(std::string configPath, const io::RunConfig& config)
        : mConfigPath(std::move(configPath)), mScenePath(config.scene), mOcioPath(config.ocioConfig) {}

    /// Throws fp::UsageError when the config names no scene.
    const io::SceneFile& scene();
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig();

private:
    std::string mConfigPath, mScenePath, mOcioPath;
    std::optional<io::SceneFile> mScene;
    OCIO_NAMESPACE::ConstConfigRcPtr mColorConfig;
};

}  // namespace fp::cli
