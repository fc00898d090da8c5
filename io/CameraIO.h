#pragma once
// Cameras in and out of files: framepass's own double-precision header attributes, the standard
// OpenEXR worldToCamera/worldToNDC pair, and the JSON camera of sidecars and scene files.
//
// Header attributes (all matrices in Imath's row-vector convention, p' = p·M, like worldToCamera):
//   framepass:worldToView, framepass:viewToClip            M44d, this frame
//   framepass:prevWorldToView, framepass:prevViewToClip    M44d, previous frame (optional)
//   framepass:sceneUnitsPerMeter                           double
//   worldToCamera, worldToNDC                              M44f, standard (float: lossy far away)
#include "passes/core/Camera.h"
#include "passes/core/Image.h"

#include <OpenEXR/ImfHeader.h>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace Imf = OPENEXR_IMF_NAMESPACE;

namespace fp::io {

void writeCameraAttributes(Imf::Header& header, const FrameCamera& camera);

/// The camera from framepass's attributes, else from worldToCamera/worldToNDC (near plane then
/// defaults to 10 cm in the file's units), else nothing.
std::optional<FrameCamera> readCameraAttributes(const Imf::Header& header, Extent extent);

/// A camera from JSON: either {"cameraToWorld": [16 row-major], "axes": "opengl"|"unreal",
/// "fovYDegrees" | "fxPixels","fyPixels","cxPixels","cyPixels", "near"} or
/// {"position", "target", "up", "fovYDegrees", "near"}. `pointer` prefixes error locations.
CameraView cameraViewFromJson(const nlohmann::json& j, Extent extent, const std::string& where);

/// A sidecar (<capture>.camera.json): a camera plus "sceneUnitsPerMeter" and "previous".
FrameCamera readCameraSidecar(const std::string& path, Extent extent);

nlohmann::json cameraViewToJson(const CameraView& view);

}  // namespace fp::io
