#pragma once
// The scene as passes see it: triangle meshes in double-precision world space, materials in
// Unreal's GBuffer terms, and lights. io/SceneLoader fills it from glTF or OBJ plus a scene JSON.
#include "foundation/Camera.h"
#include "foundation/Environment.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace fp {

struct Material {
    std::string name;
    Vec3f baseColor{0.8f, 0.8f, 0.8f};  //!< linear albedo
    float metallic = 0.0f;              //!< [0, 1]
    float specular = 0.5f;              //!< [0, 1]; F0 = 0.08·specular for dielectrics
    float roughness = 0.5f;             //!< [0, 1] perceptual (α = roughness²)
    Vec3f emission{0, 0, 0};            //!< emitted radiance
    int shadingModel = 1;               //!< algorithms §1.6 (1 = default lit)
    Vec3f subsurfaceColor{1, 1, 1};     //!< for subsurface-type models
    float opacity = 1.0f;
    float clearCoat = 0.0f;
    float clearCoatRoughness = 0.1f;
};

struct Mesh {
    std::string name;
    std::vector<Vec3d> positions;  //!< world space
    std::vector<Vec3f> normals;    //!< per vertex, optional (empty = flat shading)
    std::vector<uint32_t> indices;  //!< three per triangle
    int material = 0;
    uint32_t instanceId = 1;        //!< written to the InstanceId buffer (0 = sky)
    /// Index in Scene::lights of the light whose visible shape this mesh is (−1: none). The
    /// camera sees its emission; the light it sends to other surfaces is that light's own,
    /// which the light delivers, so the truths do not count it a second time as emission.
    int shapeOf = -1;
};

enum class LightType { Directional, Point, Spot, Rect };

struct Light {
    std::string name;
    LightType type = LightType::Point;
    Vec3f color{1, 1, 1};
    /// Directional: irradiance at normal incidence. Point/spot: radiant intensity (I, so the
    /// irradiance at distance r is I·cosθ/r²). Rect: emitted radiance.
    float intensity = 1.0f;
    Vec3d position;                //!< point, spot, rect centre
    Vec3d direction{0, -1, 0};     //!< direction the light travels (directional, spot axis)
    float sourceAngleDegrees = 0;  //!< directional: angular diameter of the source
    float radius = 0;              //!< point/spot: sphere radius (soft shadows)
    float innerConeDegrees = 0, outerConeDegrees = 45;  //!< spot half angles
    Vec3d halfU{0.5, 0, 0}, halfV{0, 0, 0.5};  //!< rect: half-extent axes; emits along halfU × halfV
    double attenuationRadius = 0;  //!< local lights: no light beyond this distance (0 = unlimited)
    int samplesPerPixel = 1;       //!< shadow rays per pixel (Unreal's light SamplesPerPixel)
    std::string shape;             //!< name of the mesh(es) that are the light's visible shape

    /// Unreal's spot mask for a point at angle acos(cosAngle) off the axis:
    /// saturate((cos − cosOuter)/(cosInner − cosOuter))²; 1 for every other light type.
    float spotMask(float cosAngle) const {
        if (type != LightType::Spot) return 1.0f;
        return spotMaskOf(cosAngle, cosOuterCone(), cosInnerCone());
    }
    float cosOuterCone() const { return std::cos(outerConeDegrees * kPiF / 180.0f); }
    float cosInnerCone() const { return std::cos(innerConeDegrees * kPiF / 180.0f); }

    /// The spot mask from the cone's cosines (for per-pixel code that has no Light); T: float or
    /// float lanes.
    template <class T>
    FP_HD static T spotMaskOf(T cosAngle, float cosOuter, float cosInner) {
        const float range = cosInner - cosOuter;
        const T t = saturateOf((cosAngle - cosOuter) / (range < 1e-4f ? 1e-4f : range));
        return t * t;
    }
};

/// Each light's name reduced to letters, digits and '_' ("Light<i>" when unnamed), made unique:
/// the suffix of its Truth.Shadow.<id> layer and of the pass names a light template gives it ({light}).
inline std::vector<std::string> lightIdentifiers(const std::vector<std::string>& names) {
    std::vector<std::string> ids;
    for (std::size_t i = 0; i < names.size(); ++i) {
        std::string n;
        for (char c : names[i]) n += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
        if (n.empty()) n = "Light" + std::to_string(i);
        const std::string base = n;
        for (int k = 2; std::find(ids.begin(), ids.end(), n) != ids.end(); ++k)
            n = base + "_" + std::to_string(k);
        ids.push_back(n);
    }
    return ids;
}

inline std::vector<std::string> lightNames(const std::vector<Light>& lights) {
    std::vector<std::string> names;
    for (const auto& l : lights) names.push_back(l.name);
    return names;
}

inline std::vector<std::string> lightIdentifiers(const std::vector<Light>& lights) {
    return lightIdentifiers(lightNames(lights));
}

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Light> lights;
    Vec3f skyColor{0, 0, 0};         //!< the backdrop the camera sees where there is no surface
    Environment environment;         //!< the sky light: what rays that leave the scene receive
    double sceneUnitsPerMeter = 100.0;

    /// The radiance mesh `m` sends to other surfaces: its emission, unless it is a light's
    /// visible shape (Mesh::shapeOf), whose light the light itself delivers.
    Vec3f emissionTowardsSurfaces(unsigned m) const {
        return meshes[m].shapeOf >= 0 ? Vec3f{} : materials[meshes[m].material].emission;
    }

    /// Unreal's constants are in centimetres; this converts them to scene units.
    double centimetre() const { return sceneUnitsPerMeter / 100.0; }
};

}  // namespace fp
