#pragma once
// Unreal's RenderLights step (reference §10, step 6) for a preset chain: when the config names a
// scene, every light gets rt_shadows → shadow_denoise → deferred_lighting, each light adding into
// the colour the previous one produced. The base pass's colour (capture:Emissive) then takes the
// place of the capture's lit SceneColor at the start of the chain, so direct light is not counted
// twice, and the display shows the lit result.
#include "passes/core/GraphDesc.h"
#include "passes/core/Scene.h"

#include <vector>

namespace fp::io {

/// Adds the per-light passes to a preset `graph` (which must hold diffuse_indirect_composite and
/// display), named after each light's identifier (lightIdentifiers, as its Truth.Shadow layer);
/// `addOutputs` also writes a lit colour EXR and a shadows EXR per frame.
void addLightPasses(GraphDesc& graph, const std::vector<Light>& lights, bool addOutputs);

}  // namespace fp::io
