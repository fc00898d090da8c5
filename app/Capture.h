#pragma once
// framepass capture's work: render a canonical capture (every GBuffer buffer, SceneColor, the
// previous frame, velocity and, when asked, the reference path tracer's Truth.* layers) of a
// scene, one EXR per frame, one part per buffer.
#include <cstdint>
#include <ostream>
#include <string>

namespace fp::app {

struct CaptureOptions {
    std::string scene;   //!< scene JSON
    std::string output;  //!< EXR path; a frame pattern for several frames
    std::string frames;  //!< frame spec; "" = `frame` alone
    int width = 0, height = 0;  //!< 0 = the scene's resolution
    int lightSamples = 16;
    int64_t frame = 1;
    bool truth = false, half = false, floatDepth = false;
    int truthSpp = 256;
    double aoRadiusMeters = 1.0;
};

/// Renders and writes every frame, a line per file on `out`.
void captureScene(const CaptureOptions& options, std::ostream& out);

}  // namespace fp::app
