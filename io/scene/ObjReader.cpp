#include "io/scene/ObjReader.h"

#include "foundation/Error.h"
#include "foundation/Limits.h"
#include "foundation/Math.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

namespace fp::io {

namespace fs = std::filesystem;

namespace {

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
    const double cosLimit = std::cos(double(angleDegrees) * kPi / 180.0);
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

}  // namespace

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

}  // namespace fp::io
