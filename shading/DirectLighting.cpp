#include "shading/DirectLighting.h"

#include "foundation/Sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp {

bool DirectLighting::hasExtent(const Light& light) {
    return light.type == LightType::Rect ||
           (light.type == LightType::Directional && light.sourceAngleDegrees > 0) ||
           (light.type != LightType::Directional && light.radius > 0);
}

LightView LightView::of(const Light& light, const Vec3d& origin) {
    LightView v;
    v.type = light.type;
    v.radiance = light.color * light.intensity;
    v.position = light.position - origin;
    v.direction = normalize(Vec3f(light.direction));
    v.halfU = Vec3f(light.halfU);
    v.halfV = Vec3f(light.halfV);
    if (light.type == LightType::Directional) {
        v.extent = float(light.sourceAngleDegrees * kPi / 360.0);
        v.tanExtent = std::tan(v.extent);
    } else if (light.type != LightType::Rect) {
        v.extent = light.radius;
    }
    v.cosOuter = light.cosOuterCone();
    v.cosInner = light.cosInnerCone();
    return v;
}

DirectLighting::DirectLighting(const RayScene& scene, int samples)
    : mScene(scene), mSamples(samples) {
    for (const Light& l : scene.scene().lights) mLights.push_back(LightView::of(l, scene.origin()));
}

LightSample DirectLighting::sample(const Light& light, const SurfacePoint& s, float u, float v) const {
    const std::vector<Light>& lights = mScene.scene().lights;
    // One of the scene's lights (every caller's): its view made once.
    if (!lights.empty() && &light >= lights.data() && &light < lights.data() + lights.size())
        return sampleLight(mLights[std::size_t(&light - lights.data())], s, u, v);
    return sampleLight(LightView::of(light, mScene.origin()), s, u, v);
}

bool DirectLighting::visible(const SurfacePoint& s, const LightSample& ls) const {
    return !mScene.occluded(s.rayOrigin(), ls.shadowDir, 0.0f, ls.shadowDistance);
}

Vec3f DirectLighting::shade(const SurfacePoint& s, Rng& rng, uint64_t& shadowRays,
                            bool shadowed) const {
    return shadeLights(*this, mSamples, s, rng, shadowRays, shadowed);
}

}  // namespace fp
