#include "screenspace/GBuffer.h"

#include <utility>

namespace fp::gbuffer {

PortSpec depthInput(std::string doc, bool optional) {
    return {.name = kDepth,
            .channels = {"Z"},
            .optional = optional,
            .captureDefault = "SceneDepth",
            .doc = std::move(doc)};
}

PortSpec normalInput() {
    return {.name = kNormal,
            .channels = {"X", "Y", "Z"},
            .captureDefault = "WorldNormal",
            .doc = "world normal"};
}

PortSpec shadingModelInput(std::string doc) {
    return {.name = kShadingModel,
            .channels = {"Y"},
            .captureDefault = "ShadingModel",
            .doc = std::move(doc)};
}

PortSpec velocityInput(std::string doc) {
    return {.name = kVelocity,
            .channels = {"X", "Y"},
            .optional = true,
            .doc = std::move(doc),
            .captureWhenNoPreviousCamera = "Velocity"};
}

PortSpec customDataInput(std::string doc, bool optional) {
    return {.name = kCustomData,
            .channels = {"R", "G", "B", "A"},
            .optional = optional,
            .captureDefault = "CustomData",
            .doc = std::move(doc)};
}

PortSpec baseColorInput(std::string doc) {
    return {.name = kBaseColor,
            .channels = {"R", "G", "B"},
            .kind = PortKind::Color,
            .captureDefault = "BaseColor",
            .doc = std::move(doc)};
}

PortSpec metallicInput(std::string doc) {
    return {
        .name = kMetallic, .channels = {"Y"}, .captureDefault = "Metallic", .doc = std::move(doc)};
}

PortSpec specularInput(std::string doc) {
    return {
        .name = kSpecular, .channels = {"Y"}, .captureDefault = "Specular", .doc = std::move(doc)};
}

PortSpec roughnessInput(std::string doc) {
    return {
        .name = kRoughness, .channels = {"Y"}, .captureDefault = "Roughness", .doc = std::move(doc)};
}

PortSpec gbufferAOInput(bool optional) {
    return {.name = kGBufferAO,
            .channels = {"Y"},
            .optional = optional,
            .captureDefault = "GBufferAO",
            .doc = "material AO"};
}

PortSpec sceneColorInput(std::string name, std::string doc) {
    return {.name = std::move(name),
            .channels = {"R", "G", "B"},
            .kind = PortKind::Color,
            .captureDefault = "SceneColor",
            .doc = std::move(doc)};
}

}  // namespace fp::gbuffer
