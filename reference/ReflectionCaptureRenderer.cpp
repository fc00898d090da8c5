#include "reference/ReflectionCaptureRenderer.h"

#include "foundation/Random.h"
#include "shading/Cubemap.h"
#include "shading/DirectLighting.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>

namespace fp {

Image renderReflectionCapture(const RayScene& scene, const Vec3d& position, int size, int lightSamples) {
    const DirectLighting lighting(scene, lightSamples);
    const Vec3f origin(position - scene.origin());
    const SkyLight& sky = scene.scene().environment.sky;
    return Cubemap::renderFaces(size, [&](const Vec3f& dir) {
        const RayHit hit = scene.intersect(origin, dir, 0.0f, std::numeric_limits<float>::infinity());
        if (!hit.hit) return sky.radiance(dir);
        const SurfacePoint s = surfaceAt(scene, hit, origin, dir);
        // Seeded by the direction's bits: the same texel gets the same light samples every run.
        Rng rng(0, int(std::bit_cast<uint32_t>(dir.x)), int(std::bit_cast<uint32_t>(dir.y) ^ std::bit_cast<uint32_t>(dir.z)), 0x5ca1ab1e);
        uint64_t rays = 0;
        // A light's visible shape sends nothing here: its light is the light's own, which the
        // deferred lighting adds (its specular highlight included), as the truth counts it once.
        return scene.scene().emissionTowardsSurfaces(hit.mesh) + lighting.shade(s, rng, rays);
    });
}

bool renderMissingReflectionCaptures(Scene& scene) {
    std::vector<ReflectionCapture>& captures = scene.environment.captures;
    if (std::none_of(captures.begin(), captures.end(),
                     [](const ReflectionCapture& c) { return c.faces.width() == 0; }))
        return false;
    const RayScene rays(scene, captures.front().position);
    for (ReflectionCapture& c : captures)
        if (c.faces.width() == 0) c.faces = renderReflectionCapture(rays, c.position);
    return true;
}

}  // namespace fp
