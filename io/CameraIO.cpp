#include "io/CameraIO.h"

#include "io/JsonFile.h"

#include "foundation/Error.h"

#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfStandardAttributes.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fp::io {

namespace {

constexpr const char* kView = "framepass:worldToView";
constexpr const char* kProj = "framepass:viewToClip";
constexpr const char* kPrevView = "framepass:prevWorldToView";
constexpr const char* kPrevProj = "framepass:prevViewToClip";
constexpr const char* kUnits = "framepass:sceneUnitsPerMeter";

// Imath multiplies row vectors (p·M); framepass's Mat4d multiplies column vectors (M·p).
Imath::M44d toImath(const Mat4d& m) {
    Imath::M44d r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r[i][j] = m(j, i);
    return r;
}
Mat4d fromImath(const Imath::M44d& m) {
    Mat4d r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r(i, j) = m[j][i];
    return r;
}

// View → OpenEXR NDC: (0,0) top-left, (1,1) bottom-right; z carries device depth; w = view z.
Mat4d viewToNdc(const CameraView& c) {
    const Mat4d p = c.projectionMatrix();
    Mat4d m = Mat4d::zero();
    m(0, 0) = 0.5 * c.fx;
    m(0, 2) = 0.5 * (c.cx + 1.0);
    m(1, 1) = -0.5 * c.fy;
    m(1, 2) = 0.5 * (1.0 - c.cy);
    m(2, 2) = p(2, 2);
    m(2, 3) = p(2, 3);
    m(3, 2) = 1.0;
    return m;
}

double number(const nlohmann::json& j, const char* key, const std::string& where) {
    if (!j.contains(key)) throw UsageError(fmt::format("{}: missing '{}'", where, key));
    if (!j[key].is_number())
        throw UsageError(fmt::format("{}/{}: must be a number, not {}", where, key,
                                     j[key].type_name()));
    const double v = j[key].get<double>();
    if (!std::isfinite(v)) throw UsageError(fmt::format("{}/{}: must be finite", where, key));
    return v;
}

// A field of view in degrees, strictly inside (0, 180): 0 makes the projection infinite and 180
// makes it zero, and both fill every reconstructed position with NaN.
double fovDegrees(const nlohmann::json& j, const char* key, const std::string& where) {
    const double v = number(j, key, where);
    if (!(v > 0.0 && v < 180.0))
        throw UsageError(fmt::format("{}/{}: {} is not a field of view in (0, 180) degrees", where,
                                     key, v));
    return v;
}

// Every camera, whatever its source, must give finite matrices: a unit, orthogonal basis, a
// positive finite focal scale and near plane. Anything else puts NaN into every pixel that the
// camera reconstructs, so it is refused where it is read.
void checkCameraView(const CameraView& c, const std::string& where, ExitCode code) {
    auto bad = [&](const std::string& what) {
        throw Error(fmt::format("{}: unusable camera: {}", where, what), code);
    };
    const Vec3d axes[3] = {c.right, c.up, c.forward};
    const char* names[3] = {"right", "up", "forward"};
    for (int i = 0; i < 3; ++i) {
        const Vec3d& a = axes[i];
        if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(a.z) ||
            std::fabs(length(a) - 1.0) > 1e-3)
            bad(fmt::format("its {} axis is not a finite unit vector (a singular or non-finite "
                            "matrix, or a zero-length direction)",
                            names[i]));
    }
    if (std::fabs(dot(c.right, c.up)) > 1e-3 || std::fabs(dot(c.up, c.forward)) > 1e-3 ||
        std::fabs(dot(c.right, c.forward)) > 1e-3)
        bad("its axes are not orthogonal (a skewed or singular matrix)");
    if (!std::isfinite(c.position.x) || !std::isfinite(c.position.y) ||
        !std::isfinite(c.position.z))
        bad("its position is not finite");
    if (!(c.fx > 0.0) || !(c.fy > 0.0) || !std::isfinite(c.fx) || !std::isfinite(c.fy) ||
        !std::isfinite(c.cx) || !std::isfinite(c.cy))
        bad(fmt::format("its projection scale is not positive and finite (fx {}, fy {}: a field "
                        "of view of 0 or 180 degrees, or a singular projection)",
                        c.fx, c.fy));
    if (!(c.nearPlane > 0.0) || !std::isfinite(c.nearPlane))
        bad(fmt::format("its near plane {} is not positive and finite", c.nearPlane));
}

Vec3d vec3(const nlohmann::json& j, const char* key, const std::string& where) {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
        throw UsageError(fmt::format("{}/{}: expected [x, y, z]", where, key));
    for (const auto& v : j[key])
        if (!v.is_number()) throw UsageError(fmt::format("{}/{}: expected numbers", where, key));
    return {j[key][0].get<double>(), j[key][1].get<double>(), j[key][2].get<double>()};
}

// Unreal's FRotator (degrees) as a camera basis: FRotationMatrix's X axis is forward, Y right,
// Z up (Unreal world axes: left-handed, Z up).
void setRotator(CameraView& c, double pitch, double yaw, double roll) {
    const double p = pitch * kPi / 180.0, y = yaw * kPi / 180.0, r = roll * kPi / 180.0;
    const double sp = std::sin(p), cp = std::cos(p), sy = std::sin(y), cy = std::cos(y);
    const double sr = std::sin(r), cr = std::cos(r);
    c.forward = {cp * cy, cp * sy, sp};
    c.right = {sr * sp * cy - cr * sy, sr * sp * sy + cr * cy, -sr * cp};
    c.up = {-(cr * sp * cy + sr * sy), cy * sr - cr * sp * sy, cr * cp};
}

// The field of view of a camera JSON: "fovYDegrees" (vertical) or "fovXDegrees" (horizontal, as
// Unreal and MRQ give it); false when it has neither.
bool setFieldOfView(CameraView& c, const nlohmann::json& j, Extent extent, const std::string& where) {
    if (j.contains("fovYDegrees")) {
        c.fy = 1.0 / std::tan(fovDegrees(j, "fovYDegrees", where) * kPi / 360.0);
        c.fx = c.fy * extent.height / extent.width;
    } else if (j.contains("fovXDegrees")) {
        c.fx = 1.0 / std::tan(fovDegrees(j, "fovXDegrees", where) * kPi / 360.0);
        c.fy = c.fx * extent.width / extent.height;
    } else {
        return false;
    }
    return true;
}

// A header attribute as a number, whichever way the writer stored it (MRQ writes strings).
std::optional<double> numberAttribute(const Imf::Header& h, const std::string& name) {
    if (const auto* a = h.findTypedAttribute<Imf::DoubleAttribute>(name)) return a->value();
    if (const auto* a = h.findTypedAttribute<Imf::FloatAttribute>(name)) return a->value();
    if (const auto* a = h.findTypedAttribute<Imf::IntAttribute>(name)) return a->value();
    if (const auto* a = h.findTypedAttribute<Imf::StringAttribute>(name)) {
        try {
            std::size_t used = 0;
            const double v = std::stod(a->value(), &used);
            if (used == a->value().size()) return v;
        } catch (const std::exception&) {
        }
        throw UsageError(fmt::format("header attribute '{}' is '{}', not a number", name,
                                     a->value()));
    }
    return std::nullopt;
}

// Movie Render Queue's camera: unreal/camera/curPos/{x,y,z}, curRot/{pitch,yaw,roll}, prevPos,
// prevRot, and the horizontal FOV under unreal/camera/<Pass>/fov; Movie Render Graph writes the
// same under unreal/layerData/<layer>/camera/. Unreal axes and centimetres.
std::optional<FrameCamera> readUnrealCamera(const Imf::Header& h, Extent extent,
                                            std::vector<std::string>& assumptions) {
    std::string prefix;  // ".../camera/"
    for (auto it = h.begin(); it != h.end(); ++it) {
        const std::string name = it.name();
        if (name.rfind("unreal/", 0) == 0 && name.ends_with("camera/curPos/x")) {
            prefix = name.substr(0, name.size() - std::string("curPos/x").size());
            if (name == "unreal/camera/curPos/x") break;  // the legacy spelling wins
        }
    }
    if (prefix.empty()) return std::nullopt;
    std::optional<double> fov = numberAttribute(h, prefix + "fov");
    for (const std::string pass : {"FinalImage", ""})
        for (auto it = h.begin(); !fov && it != h.end(); ++it) {
            const std::string name = it.name();
            if (name.rfind(prefix, 0) == 0 && name.ends_with("/fov") &&
                (pass.empty() || name == prefix + pass + "/fov"))
                fov = numberAttribute(h, name);
        }
    if (!fov) {
        // No fov: from the lens, hfov = 2·atan(sensorWidth / 2·focalLength) (both in mm).
        for (auto it = h.begin(); it != h.end() && !fov; ++it) {
            const std::string name = it.name();
            if (name.rfind(prefix, 0) != 0 || !name.ends_with("focalLength") ||
                name.ends_with("inFocalLength") || name.ends_with("axFocalLength"))
                continue;
            const std::string base = name.substr(0, name.size() - std::string("focalLength").size());
            const auto focal = numberAttribute(h, name);
            const auto sensor = numberAttribute(h, base + "sensorWidth");
            if (focal && sensor && *focal > 0 && *sensor > 0)
                fov = 2.0 * std::atan(*sensor / (2.0 * *focal)) * 180.0 / kPi;
        }
    }
    if (!fov || !(*fov > 0 && *fov < 180))
        throw UsageError(fmt::format("header: {}curPos is there but no horizontal FOV in (0, 180) "
                                     "({}<Pass>/fov, or sensorWidth and focalLength)",
                                     prefix, prefix));
    auto view = [&](const std::string& pos, const std::string& rot) -> std::optional<CameraView> {
        std::array<std::optional<double>, 6> v = {
            numberAttribute(h, prefix + pos + "/x"),     numberAttribute(h, prefix + pos + "/y"),
            numberAttribute(h, prefix + pos + "/z"),     numberAttribute(h, prefix + rot + "/pitch"),
            numberAttribute(h, prefix + rot + "/yaw"),   numberAttribute(h, prefix + rot + "/roll")};
        int given = 0;
        for (const auto& x : v) given += x.has_value();
        if (given == 0) return std::nullopt;
        if (given != 6)
            throw UsageError(fmt::format("header: {}{} and {}{} need x, y, z and pitch, yaw, roll",
                                         prefix, pos, prefix, rot));
        CameraView c;
        c.position = {*v[0], *v[1], *v[2]};
        setRotator(c, *v[3], *v[4], *v[5]);
        c.fx = 1.0 / std::tan(*fov * kPi / 360.0);
        c.fy = c.fx * extent.width / extent.height;
        c.width = extent.width;
        c.height = extent.height;
        c.nearPlane = 10.0;
        return c;
    };
    FrameCamera cam;
    cam.sceneUnitsPerMeter = 100.0;
    cam.current = *view("curPos", "curRot");
    cam.previous = view("prevPos", "prevRot");
    assumptions.push_back("near plane not in the header: assumed 10 cm (Unreal's default "
                          "r.SetNearClipPlane)");
    return cam;
}

}  // namespace

void writeCameraAttributes(Imf::Header& header, const FrameCamera& camera) {
    const CameraView& c = camera.current;
    header.insert(kView, Imf::M44dAttribute(toImath(c.viewMatrix())));
    header.insert(kProj, Imf::M44dAttribute(toImath(c.projectionMatrix())));
    if (camera.previous) {
        header.insert(kPrevView, Imf::M44dAttribute(toImath(camera.previous->viewMatrix())));
        header.insert(kPrevProj, Imf::M44dAttribute(toImath(camera.previous->projectionMatrix())));
    }
    header.insert(kUnits, Imf::DoubleAttribute(camera.sceneUnitsPerMeter));
    Imath::M44f w2c(toImath(c.viewMatrix()));
    Imath::M44f w2ndc(toImath(viewToNdc(c) * c.viewMatrix()));
    Imf::addWorldToCamera(header, w2c);
    Imf::addWorldToNDC(header, w2ndc);
}

namespace {
std::optional<FrameCamera> readHeaderCamera(const Imf::Header& header, Extent extent,
                                            std::vector<std::string>& assumptions,
                                            std::optional<double> profileUnits) {
    FrameCamera cam;
    const auto* units = header.findTypedAttribute<Imf::DoubleAttribute>(kUnits);
    if (units) cam.sceneUnitsPerMeter = units->value();
    else if (profileUnits) cam.sceneUnitsPerMeter = *profileUnits;
    const auto* view = header.findTypedAttribute<Imf::M44dAttribute>(kView);
    const auto* proj = header.findTypedAttribute<Imf::M44dAttribute>(kProj);
    if (view && proj) {
        cam.current = CameraView::fromMatrices(fromImath(view->value()), fromImath(proj->value()),
                                               extent.width, extent.height);
        const auto* pv = header.findTypedAttribute<Imf::M44dAttribute>(kPrevView);
        const auto* pp = header.findTypedAttribute<Imf::M44dAttribute>(kPrevProj);
        if (pv && pp)
            cam.previous = CameraView::fromMatrices(fromImath(pv->value()),
                                                    fromImath(pp->value()), extent.width,
                                                    extent.height);
        return cam;
    }
    if (Imf::hasWorldToCamera(header) && Imf::hasWorldToNDC(header)) {
        // Standard attributes: recover intrinsics from camera→NDC = worldToNDC · cameraToWorld.
        Mat4d w2c = fromImath(Imath::M44d(Imf::worldToCamera(header)));
        Mat4d w2n = fromImath(Imath::M44d(Imf::worldToNDC(header)));
        Mat4d c2n = w2n * inverse(w2c);
        const double s = c2n(3, 2);
        FP_CHECK(s != 0.0, "worldToNDC is not a perspective projection");
        Mat4d proj = Mat4d::zero();
        proj(0, 0) = 2.0 * c2n(0, 0) / s;
        proj(0, 2) = 2.0 * c2n(0, 2) / s - 1.0;
        proj(1, 1) = -2.0 * c2n(1, 1) / s;
        proj(1, 2) = 1.0 - 2.0 * c2n(1, 2) / s;
        proj(2, 3) = 0.1 * cam.sceneUnitsPerMeter;  // Unreal's default near plane, 10 cm
        proj(3, 2) = 1.0;
        cam.current = CameraView::fromMatrices(w2c, proj, extent.width, extent.height);
        if (!units && !profileUnits)
            assumptions.push_back("scene units not in the header: assumed 100 per metre "
                                  "(centimetres, Unreal's)");
        assumptions.push_back(fmt::format("worldToNDC has no near plane: assumed 10 cm ({} scene "
                                          "units)", 0.1 * cam.sceneUnitsPerMeter));
        return cam;
    }
    return readUnrealCamera(header, extent, assumptions);
}
}  // namespace

std::optional<FrameCamera> readCameraAttributes(const Imf::Header& header, Extent extent,
                                                std::vector<std::string>& assumptions,
                                                std::optional<double> profileUnits) {
    auto cam = readHeaderCamera(header, extent, assumptions, profileUnits);
    if (cam) {
        // The header is the frame's own data: a broken camera there fails the frame (exit 1).
        if (!(cam->sceneUnitsPerMeter > 0.0) || !std::isfinite(cam->sceneUnitsPerMeter))
            throw Error(fmt::format("header: sceneUnitsPerMeter {} is not positive",
                                    cam->sceneUnitsPerMeter));
        checkCameraView(cam->current, "header camera", ExitCode::FrameFailed);
        if (cam->previous)
            checkCameraView(*cam->previous, "header camera (previous frame)",
                            ExitCode::FrameFailed);
    }
    return cam;
}

namespace {
CameraView parseCameraView(const nlohmann::json& j, Extent extent, const std::string& where,
                           double defaultNear) {
    if (!j.is_object()) throw UsageError(fmt::format("{}: a camera must be a JSON object", where));
    const double nearPlane = j.contains("near") ? number(j, "near", where) : defaultNear;
    if (!(nearPlane > 0) || !std::isfinite(nearPlane))
        throw UsageError(fmt::format("{}/near: must be a positive number", where));
    if (extent.width <= 0 || extent.height <= 0)
        throw UsageError(fmt::format("{}: a camera needs the image size", where));
    if (j.contains("position") && j.contains("rotation")) {
        // Unreal's spelling: position and FRotator (pitch, yaw, roll in degrees), Unreal axes.
        const auto& r = j["rotation"];
        if (!r.is_object())
            throw UsageError(fmt::format("{}/rotation: expected {{\"pitch\", \"yaw\", \"roll\"}} "
                                         "in degrees", where));
        CameraView c;
        c.position = vec3(j, "position", where);
        setRotator(c, number(r, "pitch", where + "/rotation"), number(r, "yaw", where + "/rotation"),
                   number(r, "roll", where + "/rotation"));
        if (!setFieldOfView(c, j, extent, where))
            throw UsageError(fmt::format("{}: give 'fovXDegrees' (horizontal) or 'fovYDegrees'",
                                         where));
        c.width = extent.width;
        c.height = extent.height;
        c.nearPlane = nearPlane;
        return c;
    }
    if (j.contains("position")) {
        const Vec3d eye = vec3(j, "position", where);
        const Vec3d up = j.contains("up") ? vec3(j, "up", where) : Vec3d{0, 1, 0};
        Vec3d target = j.contains("target") ? vec3(j, "target", where)
                                            : eye + vec3(j, "forward", where);
        if (!(length(target - eye) > 0.0))
            throw UsageError(fmt::format("{}: 'target' is 'position' (or 'forward' is zero): no "
                                         "view direction",
                                         where));
        CameraView c = CameraView::lookAt(eye, target, up, 60.0, extent.width, extent.height,
                                          nearPlane);
        if (!setFieldOfView(c, j, extent, where))
            throw UsageError(fmt::format("{}: give 'fovYDegrees' or 'fovXDegrees'", where));
        if (length(cross(normalize(target - eye), normalize(up))) < 1e-9)
            throw UsageError(fmt::format("{}: 'up' is parallel to the view direction", where));
        return c;
    }
    if (!j.contains("cameraToWorld") || !j["cameraToWorld"].is_array() ||
        j["cameraToWorld"].size() != 16)
        throw UsageError(fmt::format(
            "{}: a camera needs 'position' (+ 'target' or 'forward') or 'cameraToWorld' (16 "
            "numbers, row-major)",
            where));
    double m[16];
    for (int i = 0; i < 16; ++i) {
        const auto& v = j["cameraToWorld"][i];
        if (!v.is_number() || !std::isfinite(v.get<double>()))
            throw UsageError(fmt::format("{}/cameraToWorld/{}: must be a finite number, not {}",
                                         where, i, v.dump()));
        m[i] = v.get<double>();
    }
    if (j.contains("axes") && !j["axes"].is_string())
        throw UsageError(fmt::format("{}/axes: must be \"opengl\" or \"unreal\", not {}", where,
                                     j["axes"].dump()));
    const std::string axes = j.value("axes", "opengl");
    const Vec3d col0{m[0], m[4], m[8]}, col1{m[1], m[5], m[9]}, col2{m[2], m[6], m[10]};
    CameraView c;
    c.position = {m[3], m[7], m[11]};
    if (axes == "opengl") {  // −Z forward, +Y up, +X right
        c.right = normalize(col0);
        c.up = normalize(col1);
        c.forward = normalize(-col2);
    } else if (axes == "unreal") {  // +X forward, +Y right, +Z up
        c.forward = normalize(col0);
        c.right = normalize(col1);
        c.up = normalize(col2);
    } else {
        throw UsageError(fmt::format("{}/axes: '{}' is not 'opengl' or 'unreal'", where, axes));
    }
    c.width = extent.width;
    c.height = extent.height;
    c.nearPlane = nearPlane;
    if (!setFieldOfView(c, j, extent, where)) {
        c.fx = 2.0 * number(j, "fxPixels", where) / extent.width;
        c.fy = 2.0 * number(j, "fyPixels", where) / extent.height;
        c.cx = 2.0 * number(j, "cxPixels", where) / extent.width - 1.0;
        c.cy = 1.0 - 2.0 * number(j, "cyPixels", where) / extent.height;
    }
    return c;
}
}  // namespace

CameraView cameraViewFromJson(const nlohmann::json& j, Extent extent, const std::string& where,
                              double defaultNear) {
    const CameraView c = parseCameraView(j, extent, where, defaultNear);
    checkCameraView(c, where, ExitCode::Usage);
    return c;
}

FrameCamera readCameraSidecar(const std::string& path, Extent extent,
                              std::vector<std::string>& assumptions,
                              std::optional<double> profileUnits) {
    // A frame whose sidecar is missing is a failed frame (1); one that is there but wrong, a
    // usage error (2) naming its JSON pointer.
    FP_CHECK(std::ifstream(path) && !std::filesystem::is_directory(path),
             "{}: cannot open the camera sidecar", path);
    const nlohmann::json j = readJsonFile(path, "camera sidecar");
    return cameraFromSidecarJson(j, extent, path, assumptions, profileUnits);
}

FrameCamera cameraFromSidecarJson(const nlohmann::json& j, Extent extent, const std::string& path,
                                  std::vector<std::string>& assumptions,
                                  std::optional<double> profileUnits) {
    FrameCamera cam;
    if (!j.is_object()) throw UsageError(fmt::format("{}: a camera sidecar is a JSON object", path));
    if (j.contains("sceneUnitsPerMeter")) {
        cam.sceneUnitsPerMeter = number(j, "sceneUnitsPerMeter", path + ":");
        if (!(cam.sceneUnitsPerMeter > 0))
            throw UsageError(fmt::format("{}: /sceneUnitsPerMeter must be positive", path));
        // The camera's positions and the capture's depths must be in one unit: a sidecar in
        // metres against a profile's centimetre depth would put every surface 100× off.
        if (profileUnits && std::fabs(cam.sceneUnitsPerMeter - *profileUnits) >
                                1e-6 * std::max(cam.sceneUnitsPerMeter, *profileUnits))
            throw UsageError(fmt::format(
                "{}: /sceneUnitsPerMeter is {}, but the capture profile's buffers are in {} "
                "scene units per metre: the camera and the depth must share a unit (write the "
                "sidecar in the profile's units, or give the profile \"sceneUnitsPerMeter\": {} "
                "and scale its depth mapping to match)",
                path, cam.sceneUnitsPerMeter, *profileUnits, cam.sceneUnitsPerMeter));
    } else if (profileUnits) {
        cam.sceneUnitsPerMeter = *profileUnits;
    } else {
        assumptions.push_back(fmt::format("{}: no 'sceneUnitsPerMeter': assumed 100 (centimetres, "
                                          "Unreal's)", path));
    }
    // Unreal's default near plane, 10 cm, in the sidecar's units.
    const double defaultNear = 0.1 * cam.sceneUnitsPerMeter;
    if (!j.contains("near"))
        assumptions.push_back(fmt::format("{}: no 'near': assumed 10 cm ({} scene units)", path,
                                          defaultNear));
    cam.current = cameraViewFromJson(j, extent, path + ":", defaultNear);
    if (j.contains("previous"))
        cam.previous = cameraViewFromJson(j["previous"], extent, path + ": /previous",
                                          cam.current.nearPlane);
    return cam;
}

FrameCamera readUnrealMatrixText(const std::string& path, Extent extent,
                                 std::optional<double> profileUnits) {
    std::ifstream in(path);
    FP_CHECK(in && !std::filesystem::is_directory(path), "{}: cannot open the camera file", path);
    // "Name: [m00 m01 m02 m03] [m10 …] [m20 …] [m30 …]" (FMatrix::ToString) or "Name: value".
    std::map<std::string, std::vector<double>> values;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const auto colon = line.find(':');
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        if (colon == std::string::npos)
            throw UsageError(fmt::format("{}:{}: expected 'Name: values', got '{}'", path, number,
                                         line));
        std::string name = line.substr(0, colon);
        name.erase(0, name.find_first_not_of(" \t"));
        name.erase(name.find_last_not_of(" \t") + 1);
        std::string rest = line.substr(colon + 1);
        for (char& c : rest)
            if (c == '[' || c == ']' || c == ',') c = ' ';
        std::istringstream numbers(rest);
        std::vector<double> v;
        for (std::string word; numbers >> word;) {
            char* end = nullptr;
            const double d = std::strtod(word.c_str(), &end);
            if (end == word.c_str() || *end != '\0' || !std::isfinite(d))
                throw UsageError(fmt::format("{}:{}: '{}' in {} is not a number", path, number,
                                             word, name));
            v.push_back(d);
        }
        values[name] = v;
    }
    auto matrix = [&](const std::string& name) {
        const auto it = values.find(name);
        if (it == values.end() || it->second.size() != 16)
            throw UsageError(fmt::format("{}: needs '{}:' with 16 numbers (Unreal's FMatrix, four "
                                         "[rows])",
                                         path, name));
        // Unreal multiplies row vectors (v·M); framepass column vectors (M·v): the transpose.
        Mat4d m;
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) m(c, r) = it->second[std::size_t(4 * r + c)];
        return m;
    };
    FrameCamera cam;
    cam.sceneUnitsPerMeter = profileUnits.value_or(100.0);  // Unreal's world is in centimetres
    cam.current = CameraView::fromMatrices(matrix("ViewMatrix"), matrix("ProjectionMatrix"),
                                           extent.width, extent.height);
    checkCameraView(cam.current, path, ExitCode::Usage);
    return cam;
}

std::optional<FoundCamera> findCamera(const CameraLookup& in) {
    FoundCamera found;
    std::string sidecar = in.sidecar;
    if (sidecar.empty() && !in.capturePath.empty() &&
        std::filesystem::exists(in.capturePath + ".camera.json"))
        sidecar = in.capturePath + ".camera.json";
    if (!sidecar.empty() && sidecar.ends_with(".txt")) {
        found.camera = readUnrealMatrixText(sidecar, in.extent, in.profileUnits);
        found.source = "Unreal matrices " + sidecar;
        found.sidecar = sidecar;
        return found;
    }
    if (!sidecar.empty()) {
        found.camera = readCameraSidecar(sidecar, in.extent, found.assumptions, in.profileUnits);
        found.source = "sidecar " + sidecar;
        found.sidecar = sidecar;
        return found;
    }
    if (!in.header) return std::nullopt;
    std::optional<FrameCamera> cam;
    try {
        cam = readCameraAttributes(*in.header, in.extent, found.assumptions, in.profileUnits);
    } catch (const Error& e) {
        // The header's errors name their attribute; the file is named here.
        throw Error(fmt::format("{}: {}", in.capturePath, e.what()), e.code());
    }
    if (!cam) return std::nullopt;
    found.camera = *cam;
    found.source = in.header->findTypedAttribute<Imf::M44dAttribute>(kView)
                       ? "header (framepass)"
                   : Imf::hasWorldToCamera(*in.header) ? "header (worldToCamera, worldToNDC)"
                                                       : "header (Unreal unreal/camera/*)";
    return found;
}

nlohmann::json frameCameraToJson(const FrameCamera& camera) {
    nlohmann::json j = cameraViewToJson(camera.current);
    j["sceneUnitsPerMeter"] = camera.sceneUnitsPerMeter;
    if (camera.previous) j["previous"] = cameraViewToJson(*camera.previous);
    return j;
}

nlohmann::json cameraViewToJson(const CameraView& c) {
    return {{"position", {c.position.x, c.position.y, c.position.z}},
            {"forward", {c.forward.x, c.forward.y, c.forward.z}},
            {"up", {c.up.x, c.up.y, c.up.z}},
            {"fovYDegrees", 360.0 / kPi * std::atan(1.0 / c.fy)},
            {"near", c.nearPlane}, {"width", c.width}, {"height", c.height}};
}

}  // namespace fp::io
