#pragma once
// Direct lighting of one surface point by every light of the scene, with ray-traced visibility.
// Point/spot/directional lights give their exact unshadowed irradiance (I·cosθ/r², E·cosθ) and
// sample their extent (sphere radius, source angle) only for the shadow; rect lights are
// integrated by area sampling. The per-light sample is public so the reference tracer can
// measure each light's visibility with the same geometry.
#include "foundation/RayScene.h"
#include "foundation/Random.h"
#include "shading/BRDF.h"

namespace fp {

struct SurfacePoint {
    Vec3f position;         //!< relative to the RayScene origin
    Vec3f normal;           //!< shading normal, facing the viewer
    Vec3f geometricNormal;  //!< facing the viewer
    Vec3f toViewer;         //!< unit V
    SurfaceBRDF brdf;
    Vec3f emission;

    /// Where rays leave the surface. The step is along the geometric normal *and* back towards
    /// the viewer: the normal alone keeps a point on a concave edge on the other surface's plane
    /// (or behind it, after rounding), where half its rays meet that surface at t ≈ 0 or pass
    /// through it; every surface the arriving ray could have hit faces the viewer, so the step
    /// back puts the origin in front of both (TruthTests: AO at a concave edge).
    Vec3f rayOrigin() const { return offsetRayOrigin(position, geometricNormal + toViewer); }
};

/// The shading point of a hit of the ray org + t·dir; both normals are turned to face the ray
/// (surfaces are two-sided, as the capture's GBuffer sees them).
SurfacePoint surfaceAt(const RayScene& scene, const RayHit& hit, const Vec3f& org, const Vec3f& dir);

/// One sample of a light as seen from a surface point.
struct LightSample {
    Vec3f L;                  //!< unit direction used for shading
    Vec3f irradiance;         //!< unshadowed, at normal incidence; zero when the light misses P
    Vec3f shadowDir;          //!< unit direction of the shadow ray (towards the sampled point)
    float shadowDistance = 0; //!< where the shadow ray stops (infinite for directional lights)

    /// False when the light sends nothing to the point (behind a rect light, outside a spot's
    /// cone): no shadow ray is worth tracing.
    bool reaches() const { return irradiance.x + irradiance.y + irradiance.z > 0.0f; }
};

class DirectLighting {
public:
    /// `samples`: shadow (and area) samples for lights with extent; punctual lights use one.
    DirectLighting(const RayScene& scene, int samples) : mScene(scene), mSamples(samples) {}

    /// Reflected radiance towards V from all lights; `shadowed` false traces no shadow rays (every
    /// light unshadowed).
    Vec3f shade(const SurfacePoint& s, Rng& rng, uint64_t& shadowRays, bool shadowed = true) const;

    /// Samples `light` at (u, v) ∈ [0,1)² for the point `s`.
    LightSample sample(const Light& light, const SurfacePoint& s, float u, float v) const;
    /// True when nothing blocks the sample's shadow ray from `s`.
    bool visible(const SurfacePoint& s, const LightSample& ls) const;
    /// Samples a light needs: 1 for a punctual light, `samples` for one with extent.
    int samplesFor(const Light& light) const { return hasExtent(light) ? mSamples : 1; }
    /// A rect light, a directional light with a source angle, a point or spot with a radius.
    static bool hasExtent(const Light& light);

private:
    const RayScene& mScene;
    int mSamples;
};

}  // namespace fp
