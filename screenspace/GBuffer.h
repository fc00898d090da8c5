#pragma once
// The GBuffer inputs that many passes read, named and declared once so a port means the same in
// every pass: its name, its channels, the capture buffer it reads when the config binds none
// (algorithms §1.5–1.7), and how its world normal is read. Each pass still says in its own words
// what it does with the buffer (the doc).
#include "foundation/Image.h"
#include "foundation/Math.h"
#include "framework/Pass.h"

#include <string>

namespace fp::gbuffer {

inline constexpr const char* kDepth = "depth";
inline constexpr const char* kNormal = "normal";
inline constexpr const char* kShadingModel = "shadingModel";
inline constexpr const char* kVelocity = "velocity";
inline constexpr const char* kCustomData = "customData";
inline constexpr const char* kBaseColor = "baseColor";
inline constexpr const char* kMetallic = "metallic";
inline constexpr const char* kSpecular = "specular";
inline constexpr const char* kRoughness = "roughness";
inline constexpr const char* kGBufferAO = "gbufferAO";

/// SceneDepth, Z: linear view depth.
PortSpec depthInput(std::string doc = "linear view depth", bool optional = false);
/// WorldNormal, X Y Z.
PortSpec normalInput();
/// ShadingModel, Y: the shading model id.
PortSpec shadingModelInput(std::string doc);
/// Optional motion, X Y in pixels towards last frame; no capture default (the capture's velocity
/// is bound explicitly where a chain has one).
PortSpec velocityInput(std::string doc);
/// CustomData, R G B A: per shading model (algorithms §1.7).
PortSpec customDataInput(std::string doc, bool optional);
/// BaseColor, R G B colour.
PortSpec baseColorInput(std::string doc = "albedo");
/// Metallic, Y.
PortSpec metallicInput(std::string doc);
/// Specular, Y (GBufferB.g).
PortSpec specularInput(std::string doc);
/// Roughness, Y (GBufferB.b).
PortSpec roughnessInput(std::string doc);
/// GBufferAO, Y: the material's AO.
PortSpec gbufferAOInput(bool optional);
/// SceneColor, R G B colour, under the pass's own port `name` (the colour it composites into).
PortSpec sceneColorInput(std::string name, std::string doc);

/// The world normal stored at pixel (x, y), as stored (callers that need a unit vector normalise).
inline Vec3f worldNormalAt(const Image& normal, int x, int y) {
    return {normal.plane(0).at(x, y), normal.plane(1).at(x, y), normal.plane(2).at(x, y)};
}

}  // namespace fp::gbuffer
