#include "shading/ReflectionHits.h"

#include "foundation/Sampling.h"

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
    s.emission = scene.scene().emissionTowardsSurfaces(hit.mesh);
    if (viewer)
        s.toViewer = *viewer;
    DiffusePathSetup paths;
    paths.scene = &scene;
    paths.lighting = how.lighting;
    paths.sky = how.sky ? how.sky->source : nullptr;
    return lightReflectionHit(EmbreeTracer{paths}, s, how.sky ? &how.sky->sh : nullptr,
                              how.shadowed, how.lighting->samples(), how.indirectBounces, rng,
                              work.shadowRays, work.indirectRays);
}

}  // namespace fp
