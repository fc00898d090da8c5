#include "io/scene/SceneLoader.h"

#include "io/scene/GltfReader.h"
#include "io/scene/ObjReader.h"
#include "io/scene/RadianceExr.h"

#include "io/CameraIO.h"
#include "io/ExrReader.h"
#include "io/JsonFile.h"
#include "io/JsonShape.h"
#include "foundation/Error.h"
#include "foundation/Limits.h"
#include "foundation/Suggest.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <filesystem>
#include <fstream>
#include <functional>

namespace fp::io {

namespace fs = std::filesystem;

namespace {

// algorithms §1.6
const std::vector<std::string> kShadingModels = {"unlit",
                                                 "default_lit",
                                                 "subsurface",
                                                 "preintegrated_skin",
                                                 "clear_coat",
                                                 "subsurface_profile",
                                                 "twosided_foliage",
                                                 "hair",
                                                 "cloth",
                                                 "eye",
                                                 "single_layer_water",
                                                 "thin_translucent"};

// The shape of a scene JSON (JsonShape.h): the keys each object may hold, with their docs.
// Unknown keys are checked against it; `framepass schema scene` writes it as a JSON Schema.
using K = JsonKind;
const JsonObjectShape kLightShape = {
    "light", "a light, added to the geometry file's",
    {{"name", K::String, "its name: rt_shadows_<name>, Truth.Shadow.<name>"},
     {"type", K::String, "default point", {}, {}, {"point", "spot", "directional", "rect"}},
     {"color", K::Vec3, "linear RGB"},
     {"intensity", K::Number, "candela (point, spot, rect) or lux (directional)", 0},
     {"position", K::Vec3, "scene units"},
     {"direction", K::Vec3, "where the light travels (directional, spot, rect)"},
     {"sourceAngleDegrees", K::Number, "directional: the sun's angular diameter", 0},
     {"radius", K::Number, "point, spot: the source radius (soft shadows)", 0},
     {"innerConeDegrees", K::Number, "spot", 0},
     {"outerConeDegrees", K::Number, "spot", 0},
     {"halfU", K::Vec3, "rect: half the rectangle's first side, as a vector"},
     {"halfV", K::Vec3, "rect: half its second side, as a vector"},
     {"attenuationRadius", K::Number, "0 = unlimited (glTF range)", 0},
     {"samplesPerPixel", K::Integer, "shadow rays", 1, 64},
     {"shape", K::String, "the mesh(es) that are the light's visible shape"}}};
const JsonObjectShape kMaterialShape = {
    "material", "an override of a material of the geometry file, by name",
    {{"baseColor", K::Vec3, "linear RGB"},
     {"metallic", K::Number, "", 0, 1},
     {"specular", K::Number, "", 0, 1},
     {"roughness", K::Number, "", 0, 1},
     {"emission", K::Vec3, "radiance"},
     {"shadingModel", K::IntegerOrString, "a name such as subsurface, or its id"},
     {"subsurfaceColor", K::Vec3, "linear RGB"},
     {"opacity", K::Number, "", 0, 1},
     {"clearCoat", K::Number, "", 0, 1},
     {"clearCoatRoughness", K::Number, "", 0, 1}}};
const JsonObjectShape kSkyLightShape = {
    "skyLight", "Unreal's movable sky light: radiance = map × colour × intensity",
    {{"color", K::Vec3, "default white"},
     {"intensity", K::Number, "default 1", 0},
     {"latLong", K::String, "an equirectangular RGB or Y EXR, relative to the scene JSON"},
     {"up", K::String, "the map's up axis (default y, glTF's)", {}, {}, {"y", "z"}},
     {"occlusionTint", K::Vec3, "linear RGB"}}};
const JsonObjectShape kCaptureShape = {
    "reflection capture", "one of Unreal's reflection capture actors",
    {{"name", K::String, ""},
     {"shape", K::String, "default sphere", {}, {}, {"sphere", "box"}},
     {"position", K::Vec3, "scene units"},
     {"radius", K::Number, "sphere: the influence radius (> 0)", 0},
     {"extent", K::Vec3, "box: half size (> 0), axis-aligned"},
     {"offset", K::Vec3, "CaptureOffset (default 0)"},
     {"transitionDistance", K::Number, "box: the fade band (default 100 cm)", 0},
     {"brightness", K::Number, "default 1", 0},
     {"cubemap", K::String, "six square power-of-two faces stacked +X, −X, +Y, −Y, +Z, −Z (EXR); without it the capture is rendered from the scene"}}};

}  // namespace

const JsonObjectShape& sceneShape() {
    static const JsonObjectShape shape = {
        "framepass scene",
        "A geometry file with cameras, lights and material overrides (docs/scenes.md).",
        {{"version", K::Integer, "1", 1, 1},
         {"geometry", K::String, ".gltf/.glb, or .obj with .mtl", {}, {}, {}, nullptr, nullptr, true},
         {"smoothAngleDegrees", K::Number, "OBJ without normals: smooth across faces meeting at less than this angle", 0, 180},
         {"sceneUnitsPerMeter", K::Number, "100 for Unreal centimetres (default)", 0},
         {"offset", K::Vec3, "added to everything (geometry, lights, cameras), in double"},
         {"camera", K::ValueMap, "{position, target or forward, up, fovYDegrees, near} or a sidecar-style camera"},
         {"previousCamera", K::ValueMap, "last frame's camera; default: camera moved back by cameraMotion"},
         {"cameraMotion", K::Vec3, "per frame"},
         {"lights", K::ObjectArray, "lights added to the geometry file's", {}, {}, {}, &kLightShape},
         {"materials", K::ObjectMap, "overrides by material name", {}, {}, {}, &kMaterialShape},
         {"sky", K::Vec3, "the backdrop colour where there is no surface (it lights nothing)"},
         {"skyLight", K::Object, "the sky light", {}, {}, {}, &kSkyLightShape},
         {"reflectionCaptures", K::ObjectArray, "reflection captures", {}, {}, {}, &kCaptureShape},
         {"resolution", K::Any, "default [width, height]"},
         {"description", K::String, "ignored"}}};
    return shape;
}

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& where, const std::string& msg) {
    throw Error(fmt::format("{}: {}: {}", file, where, msg), ExitCode::Usage);
}

void checkKeys(const nlohmann::json& j,
               const JsonObjectShape& shape,
               const std::string& file,
               const std::string& where) {
    for (const auto& [k, suggestion] : shape.unknownKeys(j))
        fail(file, where + "/" + k, "unknown key" + suggestion);
}

Vec3d vec3(const nlohmann::json& v, const std::string& file, const std::string& where) {
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number())
        fail(file, where, "expected [x, y, z]");
    const Vec3d r{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z) ||
        !std::isfinite(float(r.x)) || !std::isfinite(float(r.y)) || !std::isfinite(float(r.z)))
        fail(file, where, "expected finite numbers");
    return r;
}

float num(const nlohmann::json& v, const std::string& file, const std::string& where) {
    if (!v.is_number())
        fail(file, where, "expected a number");
    if (!std::isfinite(v.get<float>()))
        fail(file, where, "expected a finite number");
    return v.get<float>();
}

void applyMaterialOverride(Material& m,
                           const nlohmann::json& o,
                           const std::string& file,
                           const std::string& where) {
    checkKeys(o, kMaterialShape, file, where);
    if (o.contains("baseColor"))
        m.baseColor = Vec3f(vec3(o["baseColor"], file, where + "/baseColor"));
    if (o.contains("emission"))
        m.emission = Vec3f(vec3(o["emission"], file, where + "/emission"));
    if (o.contains("subsurfaceColor"))
        m.subsurfaceColor = Vec3f(vec3(o["subsurfaceColor"], file, where + "/subsurfaceColor"));
    if (o.contains("metallic"))
        m.metallic = num(o["metallic"], file, where + "/metallic");
    if (o.contains("specular"))
        m.specular = num(o["specular"], file, where + "/specular");
    if (o.contains("roughness"))
        m.roughness = num(o["roughness"], file, where + "/roughness");
    if (o.contains("opacity"))
        m.opacity = num(o["opacity"], file, where + "/opacity");
    if (o.contains("clearCoat"))
        m.clearCoat = num(o["clearCoat"], file, where + "/clearCoat");
    if (o.contains("clearCoatRoughness"))
        m.clearCoatRoughness = num(o["clearCoatRoughness"], file, where + "/clearCoatRoughness");
    if (o.contains("shadingModel")) {
        const auto& s = o["shadingModel"];
        if (s.is_number_integer() && s.get<int>() >= 0 && s.get<int>() < 12) {
            m.shadingModel = s.get<int>();
        } else if (s.is_string()) {
            auto it = std::find(kShadingModels.begin(), kShadingModels.end(), s.get<std::string>());
            if (it == kShadingModels.end())
                fail(file, where + "/shadingModel",
                     "unknown shading model '" + s.get<std::string>() + "'" +
                         didYouMean(s.get<std::string>(), kShadingModels));
            m.shadingModel = int(it - kShadingModels.begin());
        } else {
            fail(file, where + "/shadingModel", "expected a name or an id 0–11");
        }
    }
}

// The scene's reflection captures (Environment.h), sorted by radius as Unreal composites them.
std::vector<ReflectionCapture> parseReflectionCaptures(const nlohmann::json& j, const std::string& file,
                                                       const Vec3d& offset, double centimetre) {
    if (!j.is_array())
        fail(file, "/reflectionCaptures", "expected an array of {\"shape\": \"sphere\"|\"box\", \"position\", …}");
    std::vector<ReflectionCapture> captures;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const std::string where = "/reflectionCaptures/" + std::to_string(i);
        const nlohmann::json& c = j[i];
        if (!c.is_object())
            fail(file, where, "a reflection capture must be an object");
        checkKeys(c, kCaptureShape, file, where);
        ReflectionCapture rc;
        rc.name = c.contains("name") && c["name"].is_string() ? c["name"].get<std::string>() : "capture" + std::to_string(i);
        if (c.contains("shape")) {
            if (!c["shape"].is_string() || (c["shape"] != "sphere" && c["shape"] != "box"))
                fail(file, where + "/shape", "expected \"sphere\" or \"box\"");
            rc.shape = c["shape"] == "box" ? ReflectionCapture::Shape::Box : ReflectionCapture::Shape::Sphere;
        }
        if (!c.contains("position"))
            fail(file, where + "/position", "missing the capture's position [x, y, z]");
        rc.position = vec3(c["position"], file, where + "/position") + offset;
        if (c.contains("offset"))
            rc.offset = vec3(c["offset"], file, where + "/offset");
        if (c.contains("brightness"))
            rc.brightness = num(c["brightness"], file, where + "/brightness");
        if (rc.brightness < 0)
            fail(file, where + "/brightness", "expected a number ≥ 0");
        if (rc.shape == ReflectionCapture::Shape::Sphere) {
            if (!c.contains("radius"))
                fail(file, where + "/radius", "a sphere capture needs its influence radius");
            rc.radius = num(c["radius"], file, where + "/radius");
            if (!(rc.radius > 0))
                fail(file, where + "/radius", "expected a radius > 0");
        } else {
            if (!c.contains("extent"))
                fail(file, where + "/extent", "a box capture needs its half size [x, y, z]");
            rc.extent = vec3(c["extent"], file, where + "/extent");
            if (!(rc.extent.x > 0 && rc.extent.y > 0 && rc.extent.z > 0))
                fail(file, where + "/extent", "expected a half size > 0 on every axis");
            rc.radius = length(rc.extent);
            rc.transitionDistance = 100.0 * centimetre;  // Unreal's BoxTransitionDistance default
            if (c.contains("transitionDistance"))
                rc.transitionDistance = num(c["transitionDistance"], file, where + "/transitionDistance");
            if (rc.transitionDistance < 0)
                fail(file, where + "/transitionDistance", "expected a distance ≥ 0");
        }
        if (c.contains("cubemap")) {
            if (!c["cubemap"].is_string())
                fail(file, where + "/cubemap", "expected the path of a cubemap EXR (six faces stacked)");
            rc.source = (fs::path(file).parent_path() / c["cubemap"].get<std::string>()).string();
            rc.faces = readRadianceExr(rc.source, file, where + "/cubemap");
            const int w = rc.faces.width(), h = rc.faces.height();
            if (h != 6 * w || (w & (w - 1)) != 0)
                fail(file, where + "/cubemap",
                     fmt::format("{} is {}×{}: a cubemap is six square faces of a power-of-two size "
                                 "stacked top to bottom (+X, −X, +Y, −Y, +Z, −Z), {}×{} for instance",
                                 rc.source, w, h, 128, 768));
        }
        captures.push_back(std::move(rc));
    }
    std::stable_sort(captures.begin(), captures.end(),
                     [](const ReflectionCapture& a, const ReflectionCapture& b) { return a.radius < b.radius; });
    return captures;
}

// The scene's sky light (Environment.h): a constant colour, or a lat-long EXR (RGB, or Y) tinted by
// the colour, × intensity. The map is read now, so a bad file fails before any pixel is read.
SkyLight parseSkyLight(const nlohmann::json& j, const std::string& file) {
    const std::string where = "/skyLight";
    if (!j.is_object())
        fail(file, where, "expected {\"color\": [r, g, b], \"intensity\": …, \"latLong\": \"sky.exr\"}");
    checkKeys(j, kSkyLightShape, file, where);
    SkyLight sky;
    sky.enabled = true;
    if (j.contains("color"))
        sky.color = Vec3f(vec3(j["color"], file, where + "/color"));
    if (j.contains("occlusionTint"))
        sky.occlusionTint = Vec3f(vec3(j["occlusionTint"], file, where + "/occlusionTint"));
    if (j.contains("intensity"))
        sky.intensity = num(j["intensity"], file, where + "/intensity");
    for (const auto& [key, v] : {std::pair{"/color", sky.color}, std::pair{"/occlusionTint", sky.occlusionTint}})
        if (v.x < 0 || v.y < 0 || v.z < 0)
            fail(file, where + key, "a radiance cannot be negative");
    if (sky.intensity < 0)
        fail(file, where + "/intensity", "expected a number ≥ 0");
    if (j.contains("up")) {
        const nlohmann::json& up = j["up"];
        if (!up.is_string() || (up != "y" && up != "z"))
            fail(file, where + "/up", "expected \"y\" (glTF's axes) or \"z\" (Blender's and Unreal's)");
        sky.up = up == "y" ? LatLongUp::Y : LatLongUp::Z;
    }
    if (j.contains("latLong")) {
        if (!j["latLong"].is_string())
            fail(file, where + "/latLong", "expected the path of a lat-long (equirectangular) EXR");
        const fs::path map = fs::path(file).parent_path() / j["latLong"].get<std::string>();
        sky.source = map.string();
        sky.latLong = readRadianceExr(sky.source, file, where + "/latLong");
        if (sky.latLong.width() < 2)
            fail(file, where + "/latLong", fmt::format("{} is {}×{}: a lat-long map needs at least 2×1 pixels",
                                                        sky.source, sky.latLong.width(), sky.latLong.height()));
    }
    return sky;
}

Light parseLight(const nlohmann::json& j, const std::string& file, const std::string& where) {
    if (!j.is_object())
        fail(file, where, "a light must be an object");
    checkKeys(j, kLightShape, file, where);
    Light l;
    for (const char* key : {"name", "type", "shape"})
        if (j.contains(key) && !j[key].is_string())
            fail(file, where + "/" + key, fmt::format("expected text, not {}", j[key].dump()));
    l.name = j.value("name", "");
    l.shape = j.value("shape", "");
    const std::string type = j.value("type", "point");
    if (type == "point")
        l.type = LightType::Point;
    else if (type == "spot")
        l.type = LightType::Spot;
    else if (type == "directional")
        l.type = LightType::Directional;
    else if (type == "rect")
        l.type = LightType::Rect;
    else
        fail(file, where + "/type", "'" + type + "' is not point, spot, directional or rect");
    if (j.contains("color"))
        l.color = Vec3f(vec3(j["color"], file, where + "/color"));
    if (j.contains("intensity"))
        l.intensity = num(j["intensity"], file, where + "/intensity");
    if (j.contains("position"))
        l.position = vec3(j["position"], file, where + "/position");
    if (j.contains("direction"))
        l.direction = normalize(vec3(j["direction"], file, where + "/direction"));
    if (j.contains("sourceAngleDegrees"))
        l.sourceAngleDegrees = num(j["sourceAngleDegrees"], file, where + "/sourceAngleDegrees");
    if (j.contains("radius"))
        l.radius = num(j["radius"], file, where + "/radius");
    if (j.contains("innerConeDegrees"))
        l.innerConeDegrees = num(j["innerConeDegrees"], file, where + "/innerConeDegrees");
    if (j.contains("outerConeDegrees"))
        l.outerConeDegrees = num(j["outerConeDegrees"], file, where + "/outerConeDegrees");
    if (j.contains("halfU"))
        l.halfU = vec3(j["halfU"], file, where + "/halfU");
    if (j.contains("halfV"))
        l.halfV = vec3(j["halfV"], file, where + "/halfV");
    if (j.contains("attenuationRadius"))
        l.attenuationRadius = num(j["attenuationRadius"], file, where + "/attenuationRadius");
    if (j.contains("samplesPerPixel")) {
        const double spp = num(j["samplesPerPixel"], file, where + "/samplesPerPixel");
        if (spp < 1 || spp > 64 || spp != std::floor(spp))
            fail(file, where + "/samplesPerPixel", "expected an integer in 1..64");
        l.samplesPerPixel = int(spp);
    }
    // Negative light or sizes make negative or NaN radiance downstream (sqrt, division by area).
    for (int c = 0; c < 3; ++c)
        if (l.color[c] < 0.0f)
            fail(file, where + "/color", "expected values ≥ 0");
    if (l.intensity < 0.0f)
        fail(file, where + "/intensity", "expected a value ≥ 0");
    if (l.radius < 0.0f || l.sourceAngleDegrees < 0.0f || l.attenuationRadius < 0.0f)
        fail(file, where, "radius, sourceAngleDegrees and attenuationRadius must be ≥ 0");
    if (j.contains("direction") && !(length(vec3(j["direction"], file, where)) > 0.0))
        fail(file, where + "/direction", "a zero-length direction");
    if (l.type == LightType::Rect && length(cross(l.halfU, l.halfV)) <= 0.0)
        fail(file, where, "a rect light needs non-parallel, non-zero 'halfU' and 'halfV'");
    if (l.name.empty())
        l.name = type;
    return l;
}

void checkFinite(const Scene& scene, const std::string& file) {
    for (const auto& m : scene.meshes)
        for (const auto& p : m.positions)
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw Error(fmt::format("{}: mesh '{}' has a non-finite vertex", file, m.name),
                            ExitCode::Usage);
    for (const auto& m : scene.meshes)
        for (const auto& n : m.normals)
            if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z) ||
                !(length(n) > 0.0f))
                throw Error(fmt::format("{}: mesh '{}' has a zero-length or non-finite normal (or "
                                        "a node scaled to 0)",
                                        file, m.name),
                            ExitCode::Usage);
}

}  // namespace

FrameCamera SceneFile::cameraForFrame(int64_t frame, Extent extent) const {
    if (cameraJson.is_null())
        throw Error(
            fmt::format("{}: the scene has no camera (add \"camera\" or a glTF camera)", path),
            ExitCode::Usage);
    FrameCamera fc;
    fc.sceneUnitsPerMeter = scene.sceneUnitsPerMeter;
    CameraView base = cameraViewFromJson(cameraJson, extent, path + ": /camera");
    base.position += offset;
    fc.current = base;
    fc.current.position += cameraMotion * double(frame - 1);
    if (!previousCameraJson.is_null()) {
        fc.previous = cameraViewFromJson(previousCameraJson, extent, path + ": /previousCamera");
        fc.previous->position += offset;
    } else {
        fc.previous = base;
        fc.previous->position += cameraMotion * double(frame - 2);
    }
    return fc;
}

namespace {
// A light in scene units ×k: its placement and size scale; so does a point or spot light's
// radiant intensity (×k²), whose irradiance I·cosθ/r² has r in scene units.
void scaleLight(Light& l, double k) {
    if (k == 1.0) return;
    l.position = l.position * k;
    l.radius = float(l.radius * k);
    l.halfU = l.halfU * k;
    l.halfV = l.halfV * k;
    l.attenuationRadius *= k;
    if (l.type == LightType::Point || l.type == LightType::Spot) l.intensity = float(l.intensity * k * k);
}
}  // namespace

SceneFile loadScene(const std::string& path, SceneParts parts) {
    const nlohmann::json j = readJsonFile(path, "scene");
    if (!j.is_object())
        fail(path, "/", "a scene must be a JSON object");
    checkKeys(j, sceneShape(), path, "");
    SceneFile sf;
    sf.path = path;
    if (!j.contains("geometry") || !j["geometry"].is_string())
        fail(path, "/geometry", "missing the geometry file (.gltf, .glb or .obj)");
    const fs::path geometry = fs::path(path).parent_path() / j["geometry"].get<std::string>();
    const std::string ext = geometry.extension().string();
    if (!fs::exists(geometry))
        fail(path, "/geometry", geometry.string() + " does not exist");
    if (ext != ".obj" && ext != ".gltf" && ext != ".glb")
        fail(path, "/geometry", "'" + ext + "' is not .gltf, .glb or .obj");
    sf.mGeometryFile = geometry.string();

    sf.unitsDeclared = j.contains("sceneUnitsPerMeter");
    if (sf.unitsDeclared)
        sf.unitsAsWritten = sf.scene.sceneUnitsPerMeter =
            num(j["sceneUnitsPerMeter"], path, "/sceneUnitsPerMeter");
    if (!(sf.scene.sceneUnitsPerMeter > 0.0f))
        fail(path, "/sceneUnitsPerMeter", "expected a number > 0");
    if (j.contains("offset"))
        sf.offset = vec3(j["offset"], path, "/offset");
    if (j.contains("cameraMotion"))
        sf.cameraMotion = vec3(j["cameraMotion"], path, "/cameraMotion");
    if (j.contains("camera"))
        sf.cameraJson = j["camera"];
    if (j.contains("previousCamera"))
        sf.previousCameraJson = j["previousCamera"];
    if (j.contains("sky"))
        sf.scene.skyColor = Vec3f(vec3(j["sky"], path, "/sky"));
    if (j.contains("skyLight"))
        sf.scene.environment.sky = parseSkyLight(j["skyLight"], path);
    if (j.contains("reflectionCaptures"))
        sf.scene.environment.captures =
            parseReflectionCaptures(j["reflectionCaptures"], path, sf.offset, sf.scene.centimetre());
    if (j.contains("resolution")) {
        const auto& r = j["resolution"];
        if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() ||
            !r[1].is_number_integer())
            fail(path, "/resolution", "expected [width, height]");
        const int64_t w = r[0].get<int64_t>(), h = r[1].get<int64_t>();
        if (w <= 0 || h <= 0 || w > limits::kMaxImageDimension || h > limits::kMaxImageDimension ||
            w * h > limits::kMaxImagePixels)
            fail(path, "/resolution",
                 fmt::format("{}×{}: at most {} pixels a side and {} in all (the limit)", w, h,
                             limits::kMaxImageDimension, limits::kMaxImagePixels));
        sf.resolution = {int(w), int(h)};
    }
    if (j.contains("smoothAngleDegrees")) {
        const float a = num(j["smoothAngleDegrees"], path, "/smoothAngleDegrees");
        if (!(a >= 0.0f && a <= 180.0f))
            fail(path, "/smoothAngleDegrees", "expected an angle in degrees, 0 to 180");
        if (ext != ".obj")
            fail(path, "/smoothAngleDegrees",
                 "smooths an OBJ without normals; a glTF carries its own normals");
        sf.mSmoothAngleDegrees = a;
    }
    if (j.contains("materials")) {
        if (!j["materials"].is_object())
            fail(path, "/materials", "expected {name: {...}}");
        sf.mMaterialOverrides = j["materials"];
    }
    // A glTF holds lights and a camera of its own, so it is read now; an OBJ holds only meshes,
    // read when a pass needs them.
    if (parts == SceneParts::All || ext != ".obj")
        sf.loadGeometry();
    if (j.contains("lights")) {
        if (!j["lights"].is_array())
            fail(path, "/lights", "expected an array");
        for (std::size_t i = 0; i < j["lights"].size(); ++i) {
            Light l = parseLight(j["lights"][i], path, "/lights/" + std::to_string(i));
            l.position += sf.offset;  // the offset moves the whole scene in double precision
            sf.scene.lights.push_back(l);
        }
        sf.mJsonLightCount = j["lights"].size();
        if (sf.mGeometryLoaded)
            sf.markLightShapes();
    }
    return sf;
}

void SceneFile::loadGeometry() {
    if (mGeometryLoaded)
        return;
    const std::string ext = fs::path(mGeometryFile).extension().string();
    std::vector<Light> jsonLights;  // already placed; the geometry's own come first
    jsonLights.swap(scene.lights);
    if (ext == ".obj")
        loadObj(mGeometryFile, scene, mSmoothAngleDegrees);
    else
        loadGltf(mGeometryFile, *this);
    if (scene.meshes.empty())
        fail(path, "/geometry", mGeometryFile + " has no triangles");
    checkFinite(scene, mGeometryFile);
    if (!mMaterialOverrides.is_null()) {
        std::vector<std::string> names;
        for (const auto& m : scene.materials)
            names.push_back(m.name);
        for (const auto& [name, o] : mMaterialOverrides.items()) {
            const std::string& wanted = name;  // clang 14 cannot capture a structured binding
            auto it = std::find_if(scene.materials.begin(), scene.materials.end(),
                                   [&](const Material& m) { return m.name == wanted; });
            if (it == scene.materials.end())
                fail(path, "/materials/" + name,
                     "no material of that name in the geometry" + didYouMean(name, names));
            applyMaterialOverride(*it, o, path, "/materials/" + name);
        }
    }
    // The offset moves the whole scene in double precision.
    for (auto& m : scene.meshes)
        for (auto& p : m.positions)
            p = (p + offset) * mUnitScale;
    for (auto& l : scene.lights) {
        l.position += offset;
        scaleLight(l, mUnitScale);
    }
    scene.lights.insert(scene.lights.end(), jsonLights.begin(), jsonLights.end());
    mGeometryLoaded = true;
    markLightShapes();
}

void SceneFile::convertUnits(double targetUnitsPerMeter) {
    FP_CHECK(targetUnitsPerMeter > 0.0, "scene units per metre must be positive");
    const double k = targetUnitsPerMeter / scene.sceneUnitsPerMeter;
    if (k == 1.0) return;
    mUnitScale *= k;
    for (auto& m : scene.meshes)
        for (auto& p : m.positions) p = p * k;
    for (auto& l : scene.lights) scaleLight(l, k);
    for (auto& c : scene.environment.captures) {
        c.position = c.position * k;
        c.radius *= k;
        c.extent = c.extent * k;
        c.transitionDistance *= k;
        c.offset = c.offset * k;
    }
    scene.sceneUnitsPerMeter = targetUnitsPerMeter;
}

void SceneFile::markLightShapes() {
    std::vector<std::string> meshNames;
    for (auto& m : scene.meshes) {
        meshNames.push_back(m.name);
        m.shapeOf = -1;
    }
    // The scene JSON's lights come last (the geometry's own first); only they can name a shape.
    const std::size_t firstJsonLight = scene.lights.size() - mJsonLightCount;
    for (std::size_t i = firstJsonLight; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        if (l.shape.empty())
            continue;
        const std::string where = fmt::format("/lights/{}/shape", i - firstJsonLight);
        int found = 0;
        for (auto& m : scene.meshes) {
            if (m.name != l.shape)
                continue;
            if (m.shapeOf >= 0)
                fail(path, where, fmt::format("mesh '{}' is already the shape of light '{}'", m.name,
                                              scene.lights[std::size_t(m.shapeOf)].name));
            m.shapeOf = int(i);
            ++found;
        }
        if (found == 0)
            fail(path, where, fmt::format("no mesh named '{}' in {}", l.shape, mGeometryFile) +
                                  didYouMean(l.shape, meshNames));
    }
}

std::string sceneFingerprint(const SceneFile& scene) {
    std::uint64_t hash = 0xcbf29ce484222325ull;
    for (const std::string& file : {scene.path, scene.geometryFile()}) {
        std::ifstream in(file, std::ios::binary);
        FP_CHECK(in, "{}: cannot read it to fingerprint the scene", file);
        char buffer[1 << 16];
        while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
            for (std::streamsize i = 0; i < in.gcount(); ++i) {
                hash ^= (unsigned char)buffer[i];
                hash *= 0x100000001b3ull;
            }
            if (!in) break;
        }
    }
    return fmt::format("{:016x}", hash);
}

}  // namespace fp::io
