#pragma once
// Direct lighting of one surface point by every light of the scene, with ray-traced visibility.
// Point/spot/directional lights give their exact unshadowed irradiance (I·cosθ/r², E·cosθ) and
// sample their extent (sphere radius, source angle) only for the shadow; rect lights are
// integrated by area sampling.
#include "passes/core/RayScene.h"
#include "passes/core/Random.h"
#include "passes/lighting/BRDF.h"

namespace fp {

struct SurfacePoint {
    Vec3f position;         //!< relative to the RayScene origin
    Vec3f normal;           //!< shading normal, facing the viewer
    Vec3f geometricNormal;  //!< facing the viewer
    Vec3f toViewer;         //!< unit V
    SurfaceBRDF brdf;
};

class DirectLighting {
public:
    /// `samples`: shadow (and area) samples for lights with extent; punctual lights use one.
    DirectLighting(const RayScene& scene, int samples) : mScene(scene), mSamples(samples) {}

    /// Reflected radiance towards V from all lights.
    Vec3f shade(const SurfacePoint& s, Rng& rng, uint64_t& shadowRays) const;

private:
    const RayScene& mScene;
    int mSamples;
};

}  // namespace fp
