#pragma once
// The GBuffer planes a lighting pass decodes a pixel's material from (algorithms §1), as per-pixel
// code reads them on either backend, bound once from a pass's ports (HostPorts or DevicePorts).
#include "foundation/PlaneView.h"
#include "screenspace/GBuffer.h"

namespace fp {

struct MaterialViews {
    PlaneView depth, normal[3], baseColor[3], metallic, specular, roughness, shadingModel;
    PlaneView customData[4], gbufferAO;  //!< null where the capture has none (optional inputs)
};

/// Whether the pass declares the optional custom data and GBuffer AO inputs (a pass may read only
/// the inputs it declares).
enum class MaterialExtras { Declared, None };

/// The views of a pass's GBuffer inputs (gbuffer::k* ports).
template <class Ports>
MaterialViews bindMaterialViews(const Ports& ports, MaterialExtras extras = MaterialExtras::Declared) {
    MaterialViews m;
    m.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    const auto& normal = ports.input(gbuffer::kNormal)->image();
    const auto& baseColor = ports.input(gbuffer::kBaseColor)->image();
    for (int c = 0; c < 3; ++c) {
        m.normal[c] = viewOf(normal.plane(c));
        m.baseColor[c] = viewOf(baseColor.plane(c));
    }
    m.metallic = viewOf(ports.input(gbuffer::kMetallic)->image().plane(0));
    m.specular = viewOf(ports.input(gbuffer::kSpecular)->image().plane(0));
    m.roughness = viewOf(ports.input(gbuffer::kRoughness)->image().plane(0));
    m.shadingModel = viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0));
    if (extras == MaterialExtras::None) return m;
    if (const auto* customData = ports.input(gbuffer::kCustomData))
        for (int c = 0; c < 4; ++c) m.customData[c] = viewOf(customData->image().plane(c));
    if (const auto* ao = ports.input(gbuffer::kGBufferAO)) m.gbufferAO = viewOf(ao->image().plane(0));
    return m;
}

}  // namespace fp
