#include "io/CaptureSource.h"

#include "io/CameraIO.h"
#include "io/ConfigLoader.h"
#include "passes/core/Error.h"
#include "passes/core/SemanticBuffers.h"

#include <OpenEXR/ImfIntAttribute.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace fp::io {

namespace OCIO = OCIO_NAMESPACE;

std::string colorConfigPath(const std::string& explicitPath) {
    std::string path = explicitPath;
    if (path.empty())
        if (const char* env = std::getenv("OCIO"); env && *env)
            path = env;
    if (path.empty())
        path = configDirectory() + "/ocio/config.ocio";
    return path;
}

OCIO::ConstConfigRcPtr loadColorConfig(const std::string& explicitPath) {
    const std::string path = colorConfigPath(explicitPath);
    try {
        return OCIO::Config::CreateFromFile(path.c_str());
    } catch (const OCIO::Exception& e) {
        throw Error(fmt::format("{}: cannot load the OCIO config: {}", path, e.what()));
    }
}

CaptureSource::CaptureSource(Options options, CaptureProfile profile)
    : mOptions(std::move(options)), mProfile(std::move(profile)), mReader(mOptions.path) {}

FrameInfo CaptureSource::frameInfo() {
    if (mInfo)
        return *mInfo;
    FrameInfo info;
    info.number = mOptions.frame;
    info.extent = mReader.extent();
    info.firstInSequence = mOptions.firstInSequence;
    std::string sidecar = mOptions.cameraSidecar;
    if (sidecar.empty() && std::filesystem::exists(mOptions.path + ".camera.json"))
        sidecar = mOptions.path + ".camera.json";
    if (!sidecar.empty()) {
        info.camera = readCameraSidecar(sidecar, info.extent);
        info.hasCamera = true;
    } else if (auto cam = readCameraAttributes(mReader.header(), info.extent)) {
        info.camera = *cam;
        info.hasCamera = true;
    }
    mInfo = info;
    return info;
}

Texture CaptureSource::loadBuffer(const std::string& buffer, int channels) {
    const SemanticBuffer* sem = findSemanticBuffer(buffer);
    std::vector<std::string> names;
    if (sem)
        names = sem->channels;
    const auto fileChannels = mProfile.channelsFor(buffer, channels);
    if (!sem)
        for (const auto& c : fileChannels)
            names.push_back(c.substr(c.rfind('.') + 1));
    for (const auto& c : fileChannels)
        FP_CHECK(mReader.findChannel(c),
                 "{}: frame {}: buffer '{}' needs channel '{}', which the "
                 "file does not have",
                 mOptions.path, mOptions.frame, buffer, c);
    Image img = mReader.read(fileChannels, names);
    FP_CHECK(img.width() == mReader.extent().width && img.height() == mReader.extent().height,
             "{}: frame {}: buffer '{}' is {}×{}, the capture is {}×{}", mOptions.path,
             mOptions.frame, buffer, img.width(), img.height(), mReader.extent().width,
             mReader.extent().height);

    // DESIGN §5: no NaN ever reaches an output. Colour: non-finite or negative → 0. Depth: NaN or
    // negative → sky. Normals: renormalised when off unit length by more than half precision.
    const bool isColor = sem ? sem->kind == PortKind::Color : true;
    const bool isDepth = buffer == "SceneDepth" || buffer == "PrevSceneDepth";
    SanitizeCounts counts;
    for (int c = 0; c < img.channelCount(); ++c)
        for (int y = 0; y < img.height(); ++y) {
            float* row = img.plane(c).row(y);
            for (int x = 0; x < img.width(); ++x) {
                float& v = row[x];
                if (isDepth) {
                    if (std::isnan(v) || v < 0.0f) {
                        ++counts.nonFinite;
                        v = std::numeric_limits<float>::infinity();
                    }
                } else if (!std::isfinite(v)) {
                    ++counts.nonFinite;
                    v = 0.0f;
                } else if (isColor && v < 0.0f) {
                    ++counts.negative;
                    v = 0.0f;
                }
            }
        }
    if (buffer == "WorldNormal")
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x) {
                Vec3f n{img.plane(0).at(x, y), img.plane(1).at(x, y), img.plane(2).at(x, y)};
                const float len = length(n);
                if (len == 0.0f || std::fabs(len - 1.0f) < 1e-3f)
                    continue;
                ++counts.nonUnitNormals;
                for (int c = 0; c < 3; ++c)
                    img.plane(c).at(x, y) = n[c] / len;
            }
    if (counts.total() > 0 && mOptions.strict)
        throw Error(
            fmt::format("{}: frame {}: buffer '{}' has {} non-finite, {} negative and {} "
                        "non-unit values (--strict)",
                        mOptions.path, mOptions.frame, buffer, counts.nonFinite, counts.negative,
                        counts.nonUnitNormals));
    mSanitized.nonFinite += counts.nonFinite;
    mSanitized.negative += counts.negative;
    mSanitized.nonUnitNormals += counts.nonUnitNormals;
    return Texture(std::move(img));
}

const RayScene& CaptureSource::scene() {
    if (!mRayScene) {
        FP_CHECK(mOptions.scene, "a pass needs scene geometry but the config names no 'scene'");
        const FrameInfo info = frameInfo();
        mRayScene =
            std::make_unique<RayScene>(mOptions.scene().scene, info.camera.current.position);
    }
    return *mRayScene;
}

const std::vector<Light>& CaptureSource::lights() {
    FP_CHECK(mOptions.lights, "a pass needs the scene's lights but the config names no 'scene'");
    return mOptions.lights();
}

OCIO::ConstConfigRcPtr CaptureSource::colorConfig() {
    FP_CHECK(mOptions.colorConfig, "a pass needs an OCIO config but none was provided");
    return mOptions.colorConfig();
}

}  // namespace fp::io
