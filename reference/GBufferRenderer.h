#pragma once
// Renders a canonical capture from scene geometry, as a deferred renderer's GBuffer would hold it:
// one primary ray through each pixel centre (no anti-aliasing, as a rasteriser), every semantic
// buffer of docs/captures.md, SceneColor = emission + direct lighting with ray-traced shadows, and last
// frame's colour and depth from the previous camera plus the velocity between the two.
#include "foundation/Camera.h"
#include "foundation/Image.h"
#include "foundation/Scene.h"

#include <cstdint>
#include <map>
#include <string>

namespace fp {

struct CaptureSettings {
    int64_t frame = 1;      //!< absolute frame number (seeds the light sampling)
    int lightSamples = 16;  //!< shadow/area samples per light with extent, per pixel
};

struct CaptureResult {
    std::map<std::string, Image> buffers;  //!< semantic buffer name → image (canonical channels)
    uint64_t primaryRays = 0, shadowRays = 0;
};

class GBufferRenderer {
public:
    GBufferRenderer(const Scene& scene, const FrameCamera& camera, const CaptureSettings& settings)
        : mScene(scene), mCamera(camera), mSettings(settings) {}

    CaptureResult render() const;

private:
    const Scene& mScene;
    const FrameCamera& mCamera;
    CaptureSettings mSettings;
};

}  // namespace fp
