#pragma once
// The semantic buffers of a capture (docs/captures.md). A profile maps file channels onto these names;
// passes bind to them as "capture:<Name>". Truth layers ("Truth.<Name>") are open-ended.
#include "framework/Pass.h"

#include <string>
#include <vector>

namespace fp {

struct SemanticBuffer {
    const char* name;
    std::vector<std::string> channels;  //!< canonical channel suffixes
    PortKind kind;
    const char* doc;
};

inline const std::vector<SemanticBuffer>& semanticBuffers() {
    static const std::vector<SemanticBuffer> kBuffers = {
        {"SceneDepth", {"Z"}, PortKind::Data, "linear view depth, scene units; sky = +inf"},
        {"WorldNormal", {"X", "Y", "Z"}, PortKind::Data, "world-space unit normal"},
        {"BaseColor", {"R", "G", "B"}, PortKind::Color, "linear albedo"},
        {"Metallic", {"Y"}, PortKind::Data, "GBufferB.r"},
        {"Specular", {"Y"}, PortKind::Data, "GBufferB.g"},
        {"Roughness", {"Y"}, PortKind::Data, "GBufferB.b"},
        {"ShadingModel", {"Y"}, PortKind::Data, "Unreal shading-model id (algorithms §1.6)"},
        {"CustomData", {"R", "G", "B", "A"}, PortKind::Data, "GBufferD (algorithms §1.7)"},
        {"Velocity", {"X", "Y"}, PortKind::Data, "pixels to the previous position, +Y down"},
        {"SceneColor", {"R", "G", "B"}, PortKind::Color, "this frame's lit colour"},
        {"Emissive", {"R", "G", "B"}, PortKind::Color,
         "scene colour before the lights run (emissive + precomputed lighting)"},
        {"PrevSceneColor", {"R", "G", "B"}, PortKind::Color, "last frame's colour (leak-free)"},
        {"TAAHistory", {"R", "G", "B"}, PortKind::Color, "last frame's TAA history"},
        {"PrevSceneDepth", {"Z"}, PortKind::Data, "last frame's linear view depth"},
        {"GBufferAO", {"Y"}, PortKind::Data, "material ambient occlusion"},
        {"Opacity", {"Y"}, PortKind::Data, "material opacity"},
        {"InstanceId", {"Y"}, PortKind::Data, "integer instance id (0 = none)"},
    };
    return kBuffers;
}

inline const SemanticBuffer* findSemanticBuffer(const std::string& name) {
    for (const auto& b : semanticBuffers())
        if (name == b.name) return &b;
    return nullptr;
}

inline bool isTruthBuffer(const std::string& name) { return name.rfind("Truth.", 0) == 0; }

/// This frame's or last frame's linear depth (sky = +inf; reconstruction reads it).
inline bool isDepthBuffer(const std::string& name) {
    return name == "SceneDepth" || name == "PrevSceneDepth";
}

}  // namespace fp
