#pragma once
// Next-event estimation for emissive geometry: picks a point on the scene's emissive triangles
// with probability proportional to area × emitted luminance, so a small bright emitter (the
// Cornell box's light quad) is found by a shadow ray instead of by luck. Emission is two-sided,
// as the capture shades it. A light's visible shape is not an emitter here (its light comes from
// the light: Scene::emissionTowardsSurfaces).
#include "foundation/RayScene.h"

#include <vector>

namespace fp {

struct EmitterPoint {
    Vec3f position;  //!< relative to the RayScene origin
    Vec3f normal;    //!< unit geometric normal
    Vec3f emission;
    unsigned mesh = 0, triangle = 0;
    float pdfArea = 0;  //!< probability density per unit area
};

class EmitterSampler {
public:
    explicit EmitterSampler(const RayScene& scene);

    bool empty() const { return mTriangles.empty(); }
    EmitterPoint sample(float choose, float u, float v) const;
    /// Density per unit area with which sample() returns points of mesh `mesh`.
    float pdfArea(unsigned mesh) const;

private:
    struct Triangle {
        unsigned mesh, index;
        Vec3f a, b, c;
    };
    const RayScene& mScene;
    std::vector<Triangle> mTriangles;
    std::vector<double> mCdf;  //!< cumulative area × luminance, normalised to end at 1
    double mTotal = 0;         //!< Σ area × luminance
};

}  // namespace fp
