#include "io/SceneLoader.h"

#include "io/CameraIO.h"
#include "io/ExrReader.h"
#include "io/JsonFile.h"
#include "passes/core/Error.h"
#include "passes/core/Limits.h"
#include "passes/core/Suggest.h"

#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <filesystem>
#include <fstream>
#include <functional>

namespace fp::io {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kSceneKeys = {
    "version",      "geometry", "sceneUnitsPerMeter", "offset", "camera",     "previousCamera",
    "cameraMotion", "lights",   "materials",          "sky",    "resolution", "description",
    "skyLight", "reflectionCaptures", "smoothAngleDegrees"};
const std::vector<std::string> kCaptureKeys = {"name",   "shape",              "position",   "radius", "extent",
                                               "offset", "transitionDistance", "brightness", "cubemap"};
const std::vector<std::string> kSkyLightKeys = {"color", "intensity", "latLong", "up", "occlusionTint"};
const std::vector<std::string> kLightKeys = {"name",
                                             "type",
                                             "color",
                                             "intensity",
                                             "position",
                                             "direction",
                                             "sourceAngleDegrees",
                                             "radius",
                                             "innerConeDegrees",
                                             "outerConeDegrees",
                                             "halfU",
                                             "halfV",
                                             "attenuationRadius",
                                             "samplesPerPixel",
                                             "shape"};
const std::vector<std::string> kMaterialKeys = {
    "baseColor",    "metallic",        "specular", "roughness", "emission",
    "shadingModel", "subsurfaceColor", "opacity",  "clearCoat", "clearCoatRoughness"};
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

[[noreturn]] void fail(const std::string& file, const std::string& where, const std::string& msg) {
    throw Error(fmt::format("{}: {}: {}", file, where, msg), ExitCode::Usage);
}

void checkKeys(const nlohmann::json& j,
               const std::vector<std::string>& allowed,
               const std::string& file,
               const std::string& where) {
    for (const auto& [k, v] : j.items())
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
            fail(file, where + "/" + k, "unknown key" + didYouMean(k, allowed));
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
    checkKeys(o, kMaterialKeys, file, where);
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

// Reads an RGB EXR (or Y) whole and checks every pixel is finite and ≥ 0; `what` names the key
// in errors. Missing, unreadable or non-EXR files fail with the file's name.
Image readRadianceExr(const std::string& path, const std::string& file, const std::string& where) {
    std::optional<ExrReader> opened;
    try {
        opened.emplace(path);
    } catch (const Error& e) {  // missing, a folder, not an EXR: a bad scene, exit 2
        fail(file, where, e.what());
    }
    ExrReader& exr = *opened;
    std::vector<std::string> channels;
    for (const char* c : {"R", "G", "B"})
        if (exr.findChannel(c)) channels.push_back(c);
    if (channels.size() != 3) {
        if (!exr.findChannel("Y"))
            fail(file, where, path + " has neither R, G, B nor Y channels");
        channels = {"Y", "Y", "Y"};
    }
    Image image = exr.read(channels, {"R", "G", "B"});
    for (int c = 0; c < 3; ++c)
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x) {
                const float v = image.plane(c).at(x, y);
                if (!std::isfinite(v) || v < 0)
                    fail(file, where, fmt::format("{} has {} at pixel ({}, {}): radiance must be finite and ≥ 0",
                                                  path, v, x, y));
            }
    return image;
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
        checkKeys(c, kCaptureKeys, file, where);
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
    checkKeys(j, kSkyLightKeys, file, where);
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
    checkKeys(j, kLightKeys, file, where);
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

// Vertex normals for an OBJ that has none, smoothed across faces that meet at less than
// `angleDegrees` (as Blender's Auto Smooth and Maya's soften-edge angle do): each corner's normal
// is the area-weighted sum of the normals of the faces around its vertex whose normal lies within
// the angle of its own face's. Returns one normal per corner (3 per face).
std::vector<Vec3f> smoothCornerNormals(const tinyobj::attrib_t& attrib,
                                       const tinyobj::mesh_t& mesh, float angleDegrees) {
    const std::size_t faces = mesh.num_face_vertices.size();
    std::vector<Vec3d> area(faces);  // face normal × 2·area
    std::map<int, std::vector<std::size_t>> facesOf;
    for (std::size_t f = 0; f < faces; ++f) {
        Vec3d p[3];
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = std::size_t(mesh.indices[3 * f + k].vertex_index);
            p[k] = {attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]};
            facesOf[mesh.indices[3 * f + k].vertex_index].push_back(f);
        }
        area[f] = cross(p[1] - p[0], p[2] - p[0]);
    }
    const double cosLimit = std::cos(double(angleDegrees) * 3.14159265358979323846 / 180.0);
    std::vector<Vec3f> out(3 * faces);
    for (std::size_t f = 0; f < faces; ++f) {
        const double len = length(area[f]);
        for (int k = 0; k < 3; ++k) {
            Vec3d sum{0, 0, 0};
            for (std::size_t g : facesOf[mesh.indices[3 * f + k].vertex_index]) {
                const double lg = length(area[g]);
                if (len > 0 && lg > 0 && dot(area[f], area[g]) >= cosLimit * len * lg)
                    sum = sum + area[g];
            }
            out[3 * f + std::size_t(k)] =
                length(sum) > 0 ? Vec3f(normalize(sum)) : Vec3f(len > 0 ? normalize(area[f]) : Vec3d{0, 0, 1});
        }
    }
    return out;
}

void loadObj(const std::string& path, Scene& scene, std::optional<float> smoothAngleDegrees) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.mtl_search_path = fs::path(path).parent_path().string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config))
        throw Error(fmt::format("{}: cannot read OBJ: {}", path, reader.Error()), ExitCode::Usage);
    const auto& attrib = reader.GetAttrib();
    const int baseMaterial = int(scene.materials.size());
    for (const auto& mtl : reader.GetMaterials()) {
        Material m;
        m.name = mtl.name;
        m.baseColor = {mtl.diffuse[0], mtl.diffuse[1], mtl.diffuse[2]};
        m.emission = {mtl.emission[0], mtl.emission[1], mtl.emission[2]};
        m.roughness = mtl.roughness > 0.0f ? mtl.roughness : 0.5f;
        m.metallic = mtl.metallic;
        scene.materials.push_back(m);
    }
    if (scene.materials.size() == std::size_t(baseMaterial))
        scene.materials.push_back(Material{"default"});
    const auto& shapes = reader.GetShapes();
    for (std::size_t s = 0; s < shapes.size(); ++s) {
        const auto& mesh = shapes[s].mesh;
        // One framepass mesh per (shape, material): the GBuffer's material is per triangle.
        std::map<int, Mesh> byMaterial;
        // Checked first: the smoothing reads every face's three vertices.
        for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f)
            for (int k = 0; k < 3 && mesh.num_face_vertices[f] == 3 && 3 * f + 2 < mesh.indices.size(); ++k) {
                const auto idx = mesh.indices[3 * f + std::size_t(k)];
                if (idx.vertex_index < 0 || 3 * std::size_t(idx.vertex_index) + 2 >= attrib.vertices.size())
                    throw Error(
                        fmt::format("{}: shape '{}' face {} has a vertex index out of range", path,
                                    shapes[s].name, f),
                        ExitCode::Usage);
            }
        const bool allTriangles =
            std::all_of(mesh.num_face_vertices.begin(), mesh.num_face_vertices.end(),
                        [](auto n) { return n == 3; }) &&
            mesh.indices.size() == 3 * mesh.num_face_vertices.size();
        const std::vector<Vec3f> smooth = smoothAngleDegrees && allTriangles
                                              ? smoothCornerNormals(attrib, mesh, *smoothAngleDegrees)
                                              : std::vector<Vec3f>{};
        for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
            // tinyobjloader triangulates; a face it could not is not a triangle (and its indices
            // would run past the list).
            if (mesh.num_face_vertices[f] != 3 || 3 * f + 2 >= mesh.indices.size())
                throw Error(fmt::format("{}: shape '{}' face {} is not a triangle tinyobjloader "
                                        "could make",
                                        path, shapes[s].name, f),
                            ExitCode::Usage);
            const int mat =
                mesh.material_ids.empty() || mesh.material_ids[f] < 0 ? 0 : mesh.material_ids[f];
            Mesh& m = byMaterial[mat];
            for (int k = 0; k < 3; ++k) {
                const auto idx = mesh.indices[3 * f + k];
                // size_t arithmetic: 3·index overflows int for the indices a broken file holds.
                const std::size_t v = std::size_t(idx.vertex_index), n = std::size_t(idx.normal_index);
                if (idx.normal_index >= 0 && 3 * n + 2 >= attrib.normals.size())
                    throw Error(
                        fmt::format("{}: shape '{}' face {} has a normal index out of range", path,
                                    shapes[s].name, f),
                        ExitCode::Usage);
                m.positions.push_back(
                    {attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]});
                if (idx.normal_index >= 0)
                    m.normals.push_back(
                        {attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2]});
                else if (!smooth.empty())
                    m.normals.push_back(smooth[3 * f + std::size_t(k)]);
                m.indices.push_back(uint32_t(m.indices.size()));
            }
        }
        for (auto& [mat, m] : byMaterial) {
            m.name = shapes[s].name;
            m.material = baseMaterial + mat;
            m.instanceId = uint32_t(s + 1);
            if (m.normals.size() != m.positions.size())
                m.normals.clear();
            scene.meshes.push_back(std::move(m));
        }
    }
}

// Column-vector 4×4 from a glTF node (matrix or TRS).
Mat4d nodeMatrix(const tinygltf::Node& n) {
    Mat4d m;
    if (n.matrix.size() == 16) {
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                m(r, c) = n.matrix[c * 4 + r];  // glTF is column-major
        return m;
    }
    Mat4d t, r, s;
    if (n.translation.size() == 3)
        for (int i = 0; i < 3; ++i)
            t(i, 3) = n.translation[i];
    if (n.rotation.size() == 4) {
        const double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
        r(0, 0) = 1 - 2 * (y * y + z * z);
        r(0, 1) = 2 * (x * y - z * w);
        r(0, 2) = 2 * (x * z + y * w);
        r(1, 0) = 2 * (x * y + z * w);
        r(1, 1) = 1 - 2 * (x * x + z * z);
        r(1, 2) = 2 * (y * z - x * w);
        r(2, 0) = 2 * (x * z - y * w);
        r(2, 1) = 2 * (y * z + x * w);
        r(2, 2) = 1 - 2 * (x * x + y * y);
    }
    if (n.scale.size() == 3)
        for (int i = 0; i < 3; ++i)
            s(i, i) = n.scale[i];
    return t * r * s;
}

template <class T>
std::vector<T> readAccessor(const tinygltf::Model& model,
                            int index,
                            int components,
                            const std::string& path,
                            const std::string& what) {
    if (index < 0 || index >= int(model.accessors.size()))
        throw Error(fmt::format("{}: {}: accessor {} does not exist", path, what, index),
                    ExitCode::Usage);
    const auto& acc = model.accessors[index];
    const int n = tinygltf::GetNumComponentsInType(acc.type);
    if (n != components)
        throw Error(fmt::format("{}: {}: expected {} components, accessor {} has {}", path, what,
                                components, index, n),
                    ExitCode::Usage);
    auto bad = [&](const std::string& why) {
        throw Error(fmt::format("{}: {}: /accessors/{}: {}", path, what, index, why),
                    ExitCode::Usage);
    };
    if (acc.bufferView < 0) {
        // No buffer view: all zeros (glTF), but never more of them than a mesh may hold.
        if (acc.count > std::size_t(limits::kMaxImagePixels))
            bad(fmt::format("count {} without a bufferView is beyond the limit", acc.count));
        return std::vector<T>(acc.count * components, T(0));
    }
    if (acc.bufferView >= int(model.bufferViews.size()))
        bad(fmt::format("bufferView {} does not exist ({} bufferViews)", acc.bufferView,
                        model.bufferViews.size()));
    const auto& view = model.bufferViews[acc.bufferView];
    if (view.buffer < 0 || view.buffer >= int(model.buffers.size()))
        bad(fmt::format("its bufferView {} names buffer {}, which does not exist", acc.bufferView,
                        view.buffer));
    const auto& buffer = model.buffers[view.buffer];
    const int compSize = tinygltf::GetComponentSizeInBytes(acc.componentType);
    if (compSize <= 0)
        bad(fmt::format("unknown componentType {}", acc.componentType));
    if (view.byteStride > 252)
        bad(fmt::format("byteStride {} is over 252", view.byteStride));
    const std::size_t stride = view.byteStride ? view.byteStride : std::size_t(compSize) * n;
    // Every size below is bounded by the buffer's before it is multiplied, so nothing wraps
    // (an accessor count of 6148914691236517206 times a stride of 3 would).
    const std::size_t size = buffer.data.size();
    if (view.byteOffset > size || view.byteLength > size - view.byteOffset)
        bad(fmt::format("its bufferView {} lies outside buffer {}", acc.bufferView, view.buffer));
    const std::size_t viewEnd = view.byteOffset + view.byteLength;
    if (acc.byteOffset > view.byteLength || acc.count > size)
        bad(fmt::format("count {} / byteOffset {} reach past the end of its buffer", acc.count,
                        acc.byteOffset));
    const std::size_t start = view.byteOffset + acc.byteOffset;
    if (acc.count > 0 && (stride * (acc.count - 1) > viewEnd - start ||
                          start + stride * (acc.count - 1) + std::size_t(compSize) * n > viewEnd))
        bad("it reads past the end of its bufferView");
    std::vector<T> out;
    out.reserve(acc.count * n);
    for (std::size_t i = 0; i < acc.count; ++i) {
        const unsigned char* p = buffer.data.data() + start + i * stride;
        for (int c = 0; c < n; ++c) {
            const unsigned char* q = p + c * compSize;
            switch (acc.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                    float v;
                    std::memcpy(&v, q, 4);
                    out.push_back(T(v));
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
                    uint32_t v;
                    std::memcpy(&v, q, 4);
                    out.push_back(T(v));
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    uint16_t v;
                    std::memcpy(&v, q, 2);
                    out.push_back(T(v));
                    break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                    out.push_back(T(*q));
                    break;
                default:
                    throw Error(fmt::format("{}: {}: unsupported component type {}", path, what,
                                            acc.componentType),
                                ExitCode::Usage);
            }
        }
    }
    return out;
}

bool finite(const std::vector<double>& v) {
    for (double x : v)
        if (!std::isfinite(x))
            return false;
    return true;
}

// tinygltf parses the JSON but leaves every index unchecked: each one is checked here, by its
// JSON pointer, before any is followed.
void validateGltf(const tinygltf::Model& model, const std::string& path) {
    auto bad = [&](const std::string& where, const std::string& why) {
        throw Error(fmt::format("{}: {}: {}", path, where, why), ExitCode::Usage);
    };
    auto index = [&](int i, std::size_t count, const std::string& where, const char* what) {
        if (i < -1 || i >= int(count))
            bad(where, fmt::format("{} {} does not exist (the file has {})", what, i, count));
    };
    if (!model.scenes.empty() || model.defaultScene != -1)
        index(model.defaultScene, model.scenes.size(), "/scene", "scene");
    for (std::size_t s = 0; s < model.scenes.size(); ++s)
        for (std::size_t k = 0; k < model.scenes[s].nodes.size(); ++k) {
            const std::string at = fmt::format("/scenes/{}/nodes/{}", s, k);
            if (model.scenes[s].nodes[k] < 0)
                bad(at, "a negative node index");
            index(model.scenes[s].nodes[k], model.nodes.size(), at, "node");
        }
    std::vector<int> parents(model.nodes.size(), 0);
    for (std::size_t n = 0; n < model.nodes.size(); ++n) {
        const auto& node = model.nodes[n];
        const std::string at = fmt::format("/nodes/{}", n);
        for (int c : node.children)
            if (c >= 0 && c < int(parents.size()) && ++parents[c] > 1)
                bad(at + "/children", fmt::format("node {} has more than one parent (glTF nodes "
                                                  "form a tree)",
                                                  c));
        index(node.mesh, model.meshes.size(), at + "/mesh", "mesh");
        index(node.camera, model.cameras.size(), at + "/camera", "camera");
        for (std::size_t c = 0; c < node.children.size(); ++c) {
            if (node.children[c] < 0)
                bad(at + fmt::format("/children/{}", c), "a negative index");
            index(node.children[c], model.nodes.size(), at + fmt::format("/children/{}", c),
                  "node");
        }
        if (!finite(node.matrix) || !finite(node.translation) || !finite(node.rotation) ||
            !finite(node.scale))
            bad(at, "a non-finite transform");
        if (auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end()) {
            const auto& l = it->second.Get("light");
            if (!l.IsNumber() && !l.IsInt())
                bad(at + "/extensions/KHR_lights_punctual/light", "expected a light index");
            const int li = l.GetNumberAsInt();
            if (li < 0 || li >= int(model.lights.size()))
                bad(at + "/extensions/KHR_lights_punctual/light",
                    fmt::format("light {} does not exist (the file has {})", li,
                                model.lights.size()));
        }
    }
    for (std::size_t c = 0; c < model.cameras.size(); ++c) {
        const auto& cam = model.cameras[c];
        const std::string at = fmt::format("/cameras/{}/perspective", c);
        if (cam.type != "perspective")
            continue;  // orthographic cameras are not used
        if (!(cam.perspective.yfov > 0.0 && cam.perspective.yfov < kPi))
            bad(at + "/yfov",
                fmt::format("{} is not a field of view in (0, π) radians", cam.perspective.yfov));
        if (!(cam.perspective.znear > 0.0) || !std::isfinite(cam.perspective.znear))
            bad(at + "/znear", "expected a finite number > 0");
    }
    for (std::size_t m = 0; m < model.meshes.size(); ++m)
        for (std::size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            const auto& prim = model.meshes[m].primitives[p];
            const std::string at = fmt::format("/meshes/{}/primitives/{}", m, p);
            index(prim.material, model.materials.size(), at + "/material", "material");
            index(prim.indices, model.accessors.size(), at + "/indices", "accessor");
            for (const auto& [name, a] : prim.attributes) {
                if (a < 0)
                    bad(at + "/attributes/" + name, "a negative accessor index");
                index(a, model.accessors.size(), at + "/attributes/" + name, "accessor");
            }
        }
    for (std::size_t m = 0; m < model.materials.size(); ++m) {
        const auto& gm = model.materials[m];
        const std::string at = fmt::format("/materials/{}", m);
        if (gm.pbrMetallicRoughness.baseColorFactor.size() != 4 ||
            !finite(gm.pbrMetallicRoughness.baseColorFactor))
            bad(at + "/pbrMetallicRoughness/baseColorFactor", "expected 4 finite numbers");
        if (gm.emissiveFactor.size() != 3 || !finite(gm.emissiveFactor))
            bad(at + "/emissiveFactor", "expected 3 finite numbers");
        if (!std::isfinite(gm.pbrMetallicRoughness.metallicFactor) ||
            !std::isfinite(gm.pbrMetallicRoughness.roughnessFactor))
            bad(at + "/pbrMetallicRoughness", "non-finite metallic or roughness factor");
        if (auto it = gm.extensions.find("KHR_materials_emissive_strength");
            it != gm.extensions.end()) {
            const auto& s = it->second.Get("emissiveStrength");
            if (!s.IsNumber() && !s.IsInt())
                bad(at + "/extensions/KHR_materials_emissive_strength/emissiveStrength",
                    "expected a number");
            if (!(s.GetNumberAsDouble() >= 0) || !std::isfinite(s.GetNumberAsDouble()))
                bad(at + "/extensions/KHR_materials_emissive_strength/emissiveStrength",
                    "expected a finite number ≥ 0");
        }
    }
    for (std::size_t l = 0; l < model.lights.size(); ++l) {
        const auto& gl = model.lights[l];
        const std::string at = fmt::format("/extensions/KHR_lights_punctual/lights/{}", l);
        if (gl.type != "point" && gl.type != "spot" && gl.type != "directional")
            bad(at + "/type", fmt::format("'{}' is not point, spot or directional", gl.type));
        // color is optional (white when absent); when given, three finite numbers ≥ 0.
        if (!gl.color.empty() && (gl.color.size() != 3 || !finite(gl.color) ||
                                  *std::min_element(gl.color.begin(), gl.color.end()) < 0))
            bad(at + "/color", "expected 3 finite numbers ≥ 0");
        if (!(gl.intensity >= 0) || !std::isfinite(gl.intensity))
            bad(at + "/intensity", "expected a finite number ≥ 0");
        if (!(gl.range >= 0) || !std::isfinite(gl.range))
            bad(at + "/range", "expected a finite number ≥ 0");
        if (gl.type == "spot" && (!(gl.spot.innerConeAngle >= 0) || !(gl.spot.outerConeAngle > 0) ||
                                  !(gl.spot.outerConeAngle <= kPi / 2) ||
                                  !(gl.spot.innerConeAngle <= gl.spot.outerConeAngle)))
            bad(at + "/spot", "expected 0 ≤ innerConeAngle ≤ outerConeAngle ≤ π/2");
    }
}

void loadGltf(const std::string& path, SceneFile& sf) {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool binary = fs::path(path).extension() == ".glb";
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                           : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok)
        throw Error(fmt::format("{}: cannot read glTF: {}", path, err), ExitCode::Usage);
    validateGltf(model, path);
    Scene& scene = sf.scene;
    const int baseMaterial = int(scene.materials.size());
    for (const auto& gm : model.materials) {
        Material m;
        m.name = gm.name;
        const auto& pbr = gm.pbrMetallicRoughness;
        m.baseColor = {float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                       float(pbr.baseColorFactor[2])};
        m.metallic = float(pbr.metallicFactor);
        m.roughness = float(pbr.roughnessFactor);
        m.emission = {float(gm.emissiveFactor[0]), float(gm.emissiveFactor[1]),
                      float(gm.emissiveFactor[2])};
        if (auto it = gm.extensions.find("KHR_materials_emissive_strength");
            it != gm.extensions.end())
            m.emission *= float(it->second.Get("emissiveStrength").GetNumberAsDouble());
        m.opacity = float(pbr.baseColorFactor[3]);
        scene.materials.push_back(m);
    }
    scene.materials.push_back(Material{"default"});
    const int defaultMaterial = int(scene.materials.size()) - 1;

    // Nodes form a forest (glTF §3.5.2); a node met again on its own path is a cycle, which would
    // otherwise recurse until the stack overflows.
    std::vector<char> onPath(model.nodes.size(), 0);
    int depth = 0;
    std::function<void(int, const Mat4d&)> visit = [&](int nodeIndex, const Mat4d& parent) {
        if (onPath[nodeIndex])
            throw Error(fmt::format("{}: /nodes/{}: the node hierarchy has a cycle through node {}",
                                    path, nodeIndex, nodeIndex),
                        ExitCode::Usage);
        if (depth >= limits::kMaxGltfNodeDepth)
            throw Error(fmt::format("{}: /nodes/{}: the node hierarchy is deeper than {} (the "
                                    "limit)",
                                    path, nodeIndex, limits::kMaxGltfNodeDepth),
                        ExitCode::Usage);
        onPath[nodeIndex] = 1;
        ++depth;
        const auto& node = model.nodes[nodeIndex];
        const Mat4d world = parent * nodeMatrix(node);
        if (node.mesh >= 0) {
            const auto& gmesh = model.meshes[node.mesh];
            for (std::size_t p = 0; p < gmesh.primitives.size(); ++p) {
                const auto& prim = gmesh.primitives[p];
                const std::string what = fmt::format("mesh '{}' primitive {}", gmesh.name, p);
                if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1)
                    throw Error(
                        fmt::format("{}: {}: only triangle primitives are supported", path, what),
                        ExitCode::Usage);
                auto pos = prim.attributes.find("POSITION");
                if (pos == prim.attributes.end())
                    throw Error(fmt::format("{}: {}: no POSITION", path, what), ExitCode::Usage);
                const auto positions = readAccessor<double>(model, pos->second, 3, path, what);
                Mesh m;
                m.name = gmesh.name;
                m.instanceId = uint32_t(nodeIndex + 1);
                m.material = prim.material >= 0 ? baseMaterial + prim.material : defaultMaterial;
                for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
                    const auto h = world.apply({positions[i], positions[i + 1], positions[i + 2]});
                    m.positions.push_back({h[0], h[1], h[2]});
                }
                if (auto nrm = prim.attributes.find("NORMAL"); nrm != prim.attributes.end()) {
                    const auto normals = readAccessor<double>(model, nrm->second, 3, path, what);
                    if (normals.size() != positions.size())
                        throw Error(fmt::format("{}: {}: {} normals for {} positions", path, what,
                                                normals.size() / 3, positions.size() / 3),
                                    ExitCode::Usage);
                    // Normals transform by the inverse transpose of the node matrix.
                    const Mat4d nm = inverse(world).transposed();
                    for (std::size_t i = 0; i + 2 < normals.size(); i += 3) {
                        const Vec3d n{normals[i], normals[i + 1], normals[i + 2]};
                        const Vec3d t{nm(0, 0) * n.x + nm(0, 1) * n.y + nm(0, 2) * n.z,
                                      nm(1, 0) * n.x + nm(1, 1) * n.y + nm(1, 2) * n.z,
                                      nm(2, 0) * n.x + nm(2, 1) * n.y + nm(2, 2) * n.z};
                        m.normals.push_back(Vec3f(normalize(t)));
                    }
                }
                if (prim.indices >= 0) {
                    // glTF 2.0 §3.7.2.1: indices are UNSIGNED_BYTE, UNSIGNED_SHORT or
                    // UNSIGNED_INT; floats would be read as garbage indices.
                    const int indexType = model.accessors[std::size_t(prim.indices)].componentType;
                    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
                        throw Error(fmt::format("{}: {}: indices accessor {} has componentType "
                                                "{}; glTF indices are unsigned byte (5121), "
                                                "short (5123) or int (5125)",
                                                path, what, prim.indices, indexType),
                                    ExitCode::Usage);
                    for (double i : readAccessor<double>(model, prim.indices, 1, path, what)) {
                        if (i >= m.positions.size())
                            throw Error(
                                fmt::format("{}: {}: index {} is out of range", path, what, i),
                                ExitCode::Usage);
                        m.indices.push_back(uint32_t(i));
                    }
                } else {
                    for (std::size_t i = 0; i < m.positions.size(); ++i)
                        m.indices.push_back(uint32_t(i));
                }
                if (m.indices.size() % 3 != 0)
                    throw Error(
                        fmt::format("{}: {}: index count is not a multiple of 3", path, what),
                        ExitCode::Usage);
                scene.meshes.push_back(std::move(m));
            }
        }
        if (node.camera >= 0 && sf.cameraJson.is_null() &&
            model.cameras[node.camera].type == "perspective") {
            // glTF cameras look down −Z with +Y up (the "opengl" axes of a camera sidecar).
            nlohmann::json c;
            std::vector<double> m16;
            for (int r = 0; r < 4; ++r)
                for (int col = 0; col < 4; ++col)
                    m16.push_back(world(r, col));
            c["cameraToWorld"] = m16;
            c["axes"] = "opengl";
            c["fovYDegrees"] = model.cameras[node.camera].perspective.yfov * 180.0 / kPi;
            c["near"] = model.cameras[node.camera].perspective.znear;
            sf.cameraJson = c;
        }
        if (auto it = node.extensions.find("KHR_lights_punctual"); it != node.extensions.end()) {
            const int li = it->second.Get("light").GetNumberAsInt();
            const auto& gl = model.lights.at(li);
            Light l;
            l.name = gl.name.empty() ? fmt::format("light{}", li) : gl.name;
            // KHR_lights_punctual: color is optional, white by default.
            l.color = gl.color.empty()
                          ? Vec3f{1.0f, 1.0f, 1.0f}
                          : Vec3f{float(gl.color[0]), float(gl.color[1]), float(gl.color[2])};
            l.intensity = float(gl.intensity);
            l.attenuationRadius = gl.range > 0.0 ? gl.range : 0.0;  // KHR: 0/absent = unlimited
            const auto h = world.apply({0, 0, 0});
            l.position = {h[0], h[1], h[2]};
            // Lights point down their node's −Z.
            l.direction = normalize(Vec3d{-world(0, 2), -world(1, 2), -world(2, 2)});
            if (gl.type == "directional")
                l.type = LightType::Directional;
            else if (gl.type == "spot") {
                l.type = LightType::Spot;
                l.innerConeDegrees = float(gl.spot.innerConeAngle * 180.0 / kPi);
                l.outerConeDegrees = float(gl.spot.outerConeAngle * 180.0 / kPi);
            } else
                l.type = LightType::Point;
            scene.lights.push_back(l);
        }
        for (int child : node.children)
            visit(child, world);
        onPath[nodeIndex] = 0;
        --depth;
    };
    const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (!model.scenes.empty())
        for (int n : model.scenes[sceneIndex].nodes)
            visit(n, Mat4d{});
    else
        for (std::size_t n = 0; n < model.nodes.size(); ++n)
            visit(int(n), Mat4d{});
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

SceneFile loadScene(const std::string& path, SceneParts parts) {
    const nlohmann::json j = readJsonFile(path, "scene");
    if (!j.is_object())
        fail(path, "/", "a scene must be a JSON object");
    checkKeys(j, kSceneKeys, path, "");
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

    if (j.contains("sceneUnitsPerMeter"))
        sf.scene.sceneUnitsPerMeter = num(j["sceneUnitsPerMeter"], path, "/sceneUnitsPerMeter");
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
            p += offset;
    for (auto& l : scene.lights)
        l.position += offset;
    scene.lights.insert(scene.lights.end(), jsonLights.begin(), jsonLights.end());
    mGeometryLoaded = true;
    markLightShapes();
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

}  // namespace fp::io
