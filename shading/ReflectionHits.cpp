#include "shading/ReflectionHits.h"

#include <algorithm>

namespace fp {

std::shared_ptr<const ReflectedSky> ReflectedSky::of(const SkyLight& sky,
                                                     std::shared_ptr<const ReflectedSky> cached) {
    if (!sky.enabled)
        return nullptr;
    if (cached && cached->source == &sky)
        return cached;
    auto made = std::make_shared<ReflectedSky>();
    made->source = &sky;
    made->cube = Cubemap::render(Cubemap::kSkyLightSize, [&](const Vec3f& d) { return sky.radiance(d); });
    made->sh = made->cube.projectSH();
    return made;
}

Vec3f shadeReflectionHit(const RayScene& scene, const DirectLighting& lighting, const RayHit& hit,
                         const Vec3f& org, const Vec3f& L, const ReflectedSky* sky, Rng& rng,
                         uint64_t& shadowRays, bool shadowed, const Vec3f* viewer) {
    SurfacePoint s = surfaceAt(scene, hit, org, L);
    if (viewer)
        s.toViewer = *viewer;
    // The hit as Unreal's material hit shader lights it: the lights (the view vector the ray's),
    // its emission, and its diffuse colour × the sky light's SH irradiance (the precomputed
    // indirect light framepass has). A light's visible shape sends no emission here: its
    // reflection is the light's own specular, which deferred_lighting adds (algorithms §12.4).
    Vec3f radiance = scene.scene().emissionTowardsSurfaces(hit.mesh) + lighting.shade(s, rng, shadowRays, shadowed);
    if (sky)
        radiance += s.brdf.diffuseColor * sky->sh.diffuse(s.normal);
    return {std::max(radiance.x, 0.0f), std::max(radiance.y, 0.0f), std::max(radiance.z, 0.0f)};
}

}  // namespace fp
