#pragma once
// The reference path tracer behind the truth layers (docs/design.md, Truth and evaluation). It handles what framepass
// captures: Lambert diffuse plus Unreal's GGX specular (metallic/specular/roughness) and emission.
// Analytic lights are sampled by next-event estimation (DirectLighting, as the capture does);
// emissive triangles by next-event estimation combined with lobe sampling through the balance
// heuristic. A light's visible shape (Mesh::shapeOf) emits towards the camera only: its light
// reaches other surfaces through the light's own next-event estimate, so paths that meet it gather
// nothing from it and every light is counted once. Russian roulette divides by its survival
// probability, so it adds no bias. Rays that leave the scene receive the sky light's radiance
// (Scene::environment; zero without one), found by lobe sampling alone. The backdrop colour the
// camera sees (Scene::skyColor) lights nothing.
#include "foundation/RayScene.h"
#include "foundation/Random.h"
#include "shading/DirectLighting.h"
#include "reference/EmitterSampler.h"
#include "reference/ScatterLobe.h"

#include <cstdint>

namespace fp {

/// One sample of ∫ L_in(ω)·g(ω) dω at a surface point, for the lobe g.
struct Gathered {
    Vec3f oneBounce;     //!< L_in holds emission + direct light only (the capture's SceneColor)
    Vec3f full;          //!< L_in holds every bounce
    bool sampled = false;  //!< the lobe produced a direction above the surface
    bool hit = false;      //!< ... and it met a surface
    float distance = 0;    //!< ... at this distance
    int mesh = -1;         //!< ... of this mesh (Scene::meshes)
};

class PathTracer {
public:
    /// `maxBounces` only guards against albedo-1 scenes that would never end; with Russian
    /// roulette a path of albedo a reaches it with probability a^maxBounces.
    explicit PathTracer(const RayScene& scene, int maxBounces = 256)
        : mScene(scene),
          mLighting(scene, 1),
          mEmitters(scene),
          mSky(scene.scene().environment.sky),
          mMaxBounces(maxBounces) {}

    const DirectLighting& lighting() const { return mLighting; }

    Gathered gather(const SurfacePoint& s, ScatterLobe::Kind lobe, Rng& rng, uint64_t& rays) const;

private:
    /// Light s reflects towards its viewer from emissive and lit surfaces (everything except
    /// the analytic lights' direct light), by a path continued until Russian roulette ends it.
    Vec3f reflectedIndirect(const SurfacePoint& s, Rng& rng, uint64_t& rays) const;
    /// Emission reaching s through `lobe` by one sample of the emitters, MIS-weighted.
    Vec3f sampleEmitters(const SurfacePoint& s, const ScatterLobe& lobe, Rng& rng, uint64_t& rays) const;
    /// Balance-heuristic weight of emission found by a lobe sample of density `lobePdf`.
    float lobeHitWeight(const RayHit& hit, const Vec3f& dir, float lobePdf) const;

    const RayScene& mScene;
    DirectLighting mLighting;
    EmitterSampler mEmitters;
    const SkyLight& mSky;
    int mMaxBounces;
};

}  // namespace fp
