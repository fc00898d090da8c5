#pragma once
// The directional weights the reference tracer integrates incoming radiance against, each with
// its importance sampler and pdf so light sampling and lobe sampling can be combined by multiple
// importance sampling:
//   Cosine    g = cosθ/π             (the cosine-weighted mean of Truth.DiffuseIndirect, §4.8)
//   Specular  g = F·D·Vis·cosθ       (Unreal's GGX lobe alone: Truth.Specular), VNDF sampled
//   Bsdf      g = (diffuse/π + F·D·Vis)·cosθ   (the whole surface, for path vertices)
#include "foundation/Random.h"
#include "shading/DirectLighting.h"

namespace fp {

struct LobeValue {
    Vec3f weight;  //!< g(ω)
    float pdf = 0; //!< solid-angle pdf of the lobe's own sampler at ω
};

class ScatterLobe {
public:
    enum class Kind { Cosine, Specular, Bsdf };
    ScatterLobe(Kind kind, const SurfacePoint& s);

    /// False when the lobe is empty (nothing to integrate: skip it).
    bool active() const { return mActive; }
    LobeValue evaluate(const Vec3f& L) const;
    /// Draws a direction from three uniforms; false if it leaves below the surface.
    bool sample(float choose, float u, float v, Vec3f& L) const;

private:
    Kind mKind;
    const SurfacePoint& mS;
    bool mActive = true;
    float mNoV = 0, mAlpha = 0, mA2 = 0;
    float mSpecularProbability = 0;  //!< Bsdf: chance of drawing from the GGX lobe
};

}  // namespace fp
