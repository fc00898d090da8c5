#pragma once
// Renders a reflection capture's cubemap from the scene, as Unreal's capture actor records what
// its position sees: emission plus the direct light of every light (ray-traced shadows), and the
// sky light's radiance where a ray leaves the scene. Like the capture's SceneColor, it holds no
// indirect light; unlike it, a light's visible shape (Mesh::shapeOf) is dark, since that light's
// specular is already the deferred lighting's (the truth counts every light once too).
#include "foundation/Image.h"
#include "foundation/Math.h"
#include "foundation/RayScene.h"
#include "foundation/Scene.h"

namespace fp {

/// Unreal's r.ReflectionCaptureResolution default.
constexpr int kReflectionCaptureSize = 128;

/// The six faces seen from `position` (world), as Cubemap::renderFaces lays them out.
/// `scene` may have any origin; `lightSamples` shadow samples per light with extent and texel.
Image renderReflectionCapture(const RayScene& scene, const Vec3d& position, int size = kReflectionCaptureSize,
                              int lightSamples = 4);

/// Every reflection capture of `scene` that has no cubemap (the scene file named none) rendered
/// from the scene's geometry, once. Returns whether any was.
bool renderMissingReflectionCaptures(Scene& scene);

}  // namespace fp
