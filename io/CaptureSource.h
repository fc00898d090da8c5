#pragma once
// A frame read from a capture file: the header (channels, camera) when opened, pixels buffer by
// buffer as the executor asks for them, the scene's BVH and the OCIO config only if a pass needs
// them. Input pixels pass through the sanitize policy of DESIGN §5 on the way in.
#include "io/CaptureProfile.h"
#include "io/ExrReader.h"
#include "io/SceneLoader.h"
#include "passes/core/Executor.h"
#include "passes/core/RayScene.h"

#include <functional>
#include <map>
#include <memory>
#include <string>

namespace fp::io {

struct SanitizeCounts {
    uint64_t nonFinite = 0, negative = 0, nonUnitNormals = 0;
    uint64_t total() const { return nonFinite + negative + nonUnitNormals; }
};

class CaptureSource final : public FrameSource {
public:
    struct Options {
        std::string path;  //!< the capture file of this frame
        int64_t frame = 1;
        std::string cameraSidecar;                //!< "" = header, then <path>.camera.json
        std::function<const SceneFile&()> scene;  //!< loads the scene, geometry too, on first call
        std::function<const std::vector<Light>&()> lights;  //!< reads the scene's lights only
        std::function<OCIO_NAMESPACE::ConstConfigRcPtr()> colorConfig;  //!< loads on first call
        bool strict = false;  //!< bad input pixels are an error instead of sanitized
        bool firstInSequence = true;
    };
    CaptureSource(Options options, CaptureProfile profile);

    FrameInfo frameInfo() override;
    Texture loadBuffer(const std::string& buffer, int channels) override;
    const RayScene& scene() override;
    const std::vector<Light>& lights() override;
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() override;

    ExrReader& reader() { return mReader; }
    const SanitizeCounts& sanitized() const { return mSanitized; }

private:
    Options mOptions;
    CaptureProfile mProfile;
    ExrReader mReader;
    std::optional<FrameInfo> mInfo;
    std::unique_ptr<RayScene> mRayScene;
    SanitizeCounts mSanitized;
};

/// The OCIO config to use: `explicitPath`, else $OCIO, else configs/ocio/config.ocio.
OCIO_NAMESPACE::ConstConfigRcPtr loadColorConfig(const std::string& explicitPath);
/// The path loadColorConfig(explicitPath) reads.
std::string colorConfigPath(const std::string& explicitPath);

}  // namespace fp::io
