#include "io/scene/GltfReader.h"

#include "foundation/Error.h"
#include "foundation/Limits.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>

namespace fp::io {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

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

}  // namespace fp::io
