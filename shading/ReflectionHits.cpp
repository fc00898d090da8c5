#include "shading/ReflectionHits.h"

#include "foundation/Sampling.h"
#include "shading/DiffusePaths.h"

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

Vec3f shadeReflectionHit(const ReflectionHitLighting& how, const RayHit& hit, const Vec3f& org,
                         const Vec3f& L, Rng& rng, ReflectionHitWork& work, const Vec3f* viewer) {
    const RayScene& scene = *how.scene;
    SurfacePoint s = surfaceAt(scene, hit, org, L);
    if (viewer)
        s.toViewer = *viewer;
    // The hit as Unreal's material hit shader lights it: the lights (the view vector the ray's),
    // its emission, and its diffuse colour × its indirect light. A light's visible shape sends
    // no emission here: its reflection is the light's own specular, which deferred_lighting adds
    // (algorithms §12.4).
    Vec3f radiance = scene.scene().emissionTowardsSurfaces(hit.mesh) +
                     how.lighting->shade(s, rng, work.shadowRays, how.shadowed);
    if (how.indirectBounces > 0) {
        // One cosine path: its radiance is the hit's irradiance/π, as the SH's diffuse term is.
        DiffusePathSetup path;
        path.scene = &scene;
        path.lighting = how.lighting;
        path.lights = &scene.scene().lights;
        path.sky = how.sky ? how.sky->source : nullptr;
        path.skyOnFirstRay = true;
        path.emissionAtHits = true;
        path.bounces = how.indirectBounces;
        path.nee = 1;
        const float u = rng.nextFloat(), v = rng.nextFloat();
        const Vec3f dir = cosineHemisphere(s.normal, u, v);
        radiance += s.brdf.diffuseColor *
                    traceDiffusePath(path, s.rayOrigin(), dir, 0.0f, rng, work.indirectRays,
                                     work.shadowRays).radiance;
    } else if (how.sky) {
        radiance += s.brdf.diffuseColor * how.sky->sh.diffuse(s.normal);
    }
    return {std::max(radiance.x, 0.0f), std::max(radiance.y, 0.0f), std::max(radiance.z, 0.0f)};
}

}  // namespace fp
