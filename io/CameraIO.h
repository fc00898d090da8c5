#pragma once
// Cameras in and out of files: framepass's own double-precision header attributes, the standard
// OpenEXR worldToCamera/worldToNDC pair, and the JSON camera of sidecars and scene files.
//
// Header attributes (all matrices in Imath's row-vector convention, p' = p·M, like worldToCamera):
//   framepass:worldToView, framepass:viewToClip            M44d, this frame
//   framepass:prevWorldToView, framepass:prevViewToClip    M44d, previous frame (optional)
//   framepass:sceneUnitsPerMeter                           double
//   worldToCamera, worldToNDC                              M44f, standard (float: lossy far away)
#include "foundation/Camera.h"
#include "foundation/Image.h"

#include <OpenEXR/ImfHeader.h>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>


namespace fp::io {

void writeCameraAttributes(Imf::Header& header, const FrameCamera& camera);

/// The camera from framepass's attributes, else from worldToCamera/worldToNDC, else from Unreal
/// Movie Render Queue's unreal/camera/* (or Movie Render Graph's unreal/layerData/<layer>/
/// camera/*) attributes, else nothing. Values the header does not give (near plane, units) are
/// assumed and said in `assumptions`; `profileUnits` are the capture profile's scene units.
std::optional<FrameCamera> readCameraAttributes(const Imf::Header& header, Extent extent,
                                                std::vector<std::string>& assumptions,
                                                std::optional<double> profileUnits = {});

/// A camera from JSON: {"cameraToWorld": [16 row-major], "axes": "opengl"|"unreal",
/// "fovYDegrees" | "fovXDegrees" | "fxPixels","fyPixels","cxPixels","cyPixels", "near"},
/// {"position", "target" | "forward", "up", "fovYDegrees" | "fovXDegrees", "near"}, or Unreal's
/// {"position", "rotation": {"pitch", "yaw", "roll"}, "fovXDegrees", "near"} (degrees, Unreal
/// axes). `where` prefixes error locations; `defaultNear` stands in for a missing "near".
CameraView cameraViewFromJson(const nlohmann::json& j, Extent extent, const std::string& where,
                              double defaultNear = 10.0);

/// A sidecar (<capture>.camera.json): a camera plus "sceneUnitsPerMeter" and "previous". A
/// missing "sceneUnitsPerMeter" is the profile's, else 100; a missing "near" is 10 cm: both are
/// said in `assumptions`.
FrameCamera readCameraSidecar(const std::string& path, Extent extent,
                              std::vector<std::string>& assumptions,
                              std::optional<double> profileUnits = {});
/// The camera of a sidecar's JSON object, without the file (a camera handed over in memory);
/// `where` names it in errors and assumptions.
FrameCamera cameraFromSidecarJson(const nlohmann::json& j, Extent extent, const std::string& where,
                                  std::vector<std::string>& assumptions,
                                  std::optional<double> profileUnits = {});
/// A frame's camera as sidecar JSON (cameraViewToJson, "sceneUnitsPerMeter", "previous"), which
/// cameraFromSidecarJson reads back (off-centre projections are not written).
nlohmann::json frameCameraToJson(const FrameCamera& camera);

/// Where a frame's camera comes from, in the order `run` uses: the given sidecar, else
/// <capturePath>.camera.json beside the capture, else the header.
/// A camera written as Unreal's matrices in text, as G-buffer datasets of neural-rendering work
/// dump them: lines "ViewMatrix: [..] [..] [..] [..]" and "ProjectionMatrix: …" (FMatrix
/// rows, row-vector convention; ClipToView, FOV and clip distances may follow and are not
/// needed). No previous camera: that is frame N−1's file.
FrameCamera readUnrealMatrixText(const std::string& path, Extent extent,
                                 std::optional<double> profileUnits);

struct CameraLookup {
    std::string sidecar;
    std::string capturePath;
    const Imf::Header* header = nullptr;
    Extent extent;
    std::optional<double> profileUnits;
};
struct FoundCamera {
    FrameCamera camera;
    std::string source;                    //!< "sidecar <path>", "header (…)"
    std::string sidecar;                   //!< the sidecar read, "" for the header
    std::vector<std::string> assumptions;  //!< values not given and assumed
};
std::optional<FoundCamera> findCamera(const CameraLookup& lookup);

nlohmann::json cameraViewToJson(const CameraView& view);

}  // namespace fp::io
