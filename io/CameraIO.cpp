#include "io/CameraIO.h"

#include "passes/core/Error.h"

#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfStandardAttributes.h>

#include <fstream>

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
        throw UsageError(fmt::format("{}/{}: must be a number", where, key));
    return j[key].get<double>();
}

Vec3d vec3(const nlohmann::json& j, const char* key, const std::string& where) {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
        throw UsageError(fmt::format("{}/{}: expected [x, y, z]", where, key));
    for (const auto& v : j[key])
        if (!v.is_number()) throw UsageError(fmt::format("{}/{}: expected numbers", where, key));
    return {j[key][0].get<double>(), j[key][1].get<double>(), j[key][2].get<double>()};
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

std::optional<FrameCamera> readCameraAttributes(const Imf::Header& header, Extent extent) {
    FrameCamera cam;
    if (const auto* u = header.findTypedAttribute<Imf::DoubleAttribute>(kUnits))
        cam.sceneUnitsPerMeter = u->value();
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
        return cam;
    }
    return std::nullopt;
}

CameraView cameraViewFromJson(const nlohmann::json& j, Extent extent, const std::string& where) {
    if (!j.is_object()) throw UsageError(fmt::format("{}: a camera must be a JSON object", where));
    const double nearPlane = j.contains("near") ? number(j, "near", where) : 10.0;
    if (j.contains("position")) {
        const Vec3d eye = vec3(j, "position", where);
        const Vec3d up = j.contains("up") ? vec3(j, "up", where) : Vec3d{0, 1, 0};
        Vec3d target = j.contains("target") ? vec3(j, "target", where)
                                            : eye + vec3(j, "forward", where);
        CameraView c = CameraView::lookAt(eye, target, up, number(j, "fovYDegrees", where),
                                          extent.width, extent.height, nearPlane);
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
    for (int i = 0; i < 16; ++i) m[i] = j["cameraToWorld"][i].get<double>();
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
    if (j.contains("fovYDegrees")) {
        c.fy = 1.0 / std::tan(number(j, "fovYDegrees", where) * kPi / 360.0);
        c.fx = c.fy * extent.height / extent.width;
    } else {
        c.fx = 2.0 * number(j, "fxPixels", where) / extent.width;
        c.fy = 2.0 * number(j, "fyPixels", where) / extent.height;
        c.cx = 2.0 * number(j, "cxPixels", where) / extent.width - 1.0;
        c.cy = 1.0 - 2.0 * number(j, "cyPixels", where) / extent.height;
    }
    return c;
}

FrameCamera readCameraSidecar(const std::string& path, Extent extent) {
    std::ifstream in(path);
    FP_CHECK(in, "{}: cannot open the camera sidecar", path);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(in, nullptr, true, true);
    } catch (const std::exception& e) {
        throw UsageError(fmt::format("{}: not valid JSON: {}", path, e.what()));
    }
    FrameCamera cam;
    cam.current = cameraViewFromJson(j, extent, path);
    cam.sceneUnitsPerMeter = j.value("sceneUnitsPerMeter", 100.0);
    if (j.contains("previous"))
        cam.previous = cameraViewFromJson(j["previous"], extent, path + ": /previous");
    return cam;
}

nlohmann::json cameraViewToJson(const CameraView& c) {
    return {{"position", {c.position.x, c.position.y, c.position.z}},
            {"forward", {c.forward.x, c.forward.y, c.forward.z}},
            {"up", {c.up.x, c.up.y, c.up.z}},
            {"fovYDegrees", 360.0 / kPi * std::atan(1.0 / c.fy)},
            {"near", c.nearPlane}, {"width", c.width}, {"height", c.height}};
}

}  // namespace fp::io
