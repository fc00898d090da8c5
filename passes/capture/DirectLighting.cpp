#include "passes/capture/DirectLighting.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp {

namespace {

// Orthonormal basis around unit n (Duff et al. branchless ONB, reference §1.9).
void basis(const Vec3f& n, Vec3f& t, Vec3f& b) {
    const float s = n.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (s + n.z);
    const float c = n.x * n.y * a;
    t = {1.0f + s * a * n.x * n.x, s * c, -s * n.x};
    b = {c, s + a * n.y * n.y, -n.y};
}

// Jittered stratified 2D sample k of n (n rounded to a square grid).
void stratified(int k, int n, Rng& rng, float& u, float& v) {
    const int side = std::max(1, int(std::lround(std::sqrt(float(n)))));
    if (side * side != n) {
        u = rng.nextFloat();
        v = rng.nextFloat();
        return;
    }
    u = (float(k % side) + rng.nextFloat()) / float(side);
    v = (float(k / side) + rng.nextFloat()) / float(side);
}

}  // namespace

Vec3f DirectLighting::shade(const SurfacePoint& s, Rng& rng, uint64_t& shadowRays) const {
    Vec3f total;
    const Vec3f P = s.position;
    // Offset along the geometric normal, relative to the distance from the eye so the bias is
    // a fixed fraction of float precision wherever the point is.
    const float bias = 1e-4f * (1.0f + length(P));
    const Vec3f origin = P + s.geometricNormal * bias;
    for (const Light& light : mScene.scene().lights) {
        const Vec3f color = light.color * light.intensity;
        if (light.type == LightType::Rect) {
            const Vec3f c = Vec3f(light.position - mScene.origin());
            const Vec3f hu = Vec3f(light.halfU), hv = Vec3f(light.halfV);
            const Vec3f nl = normalize(cross(hu, hv));
            const float area = 4.0f * length(cross(hu, hv));
            Vec3f sum;
            for (int k = 0; k < mSamples; ++k) {
                float u, v;
                stratified(k, mSamples, rng, u, v);
                const Vec3f q = c + hu * (2.0f * u - 1.0f) + hv * (2.0f * v - 1.0f);
                const Vec3f d = q - origin;
                const float dist = length(d);
                const Vec3f L = d / dist;
                const float cosL = -dot(L, nl), NoL = dot(s.normal, L);
                if (cosL <= 0.0f || NoL <= 0.0f) continue;
                ++shadowRays;
                // Stop just short of the emitter so its own quad does not shadow it.
                if (mScene.occluded(origin, L, 0.0f, dist * (1.0f - 1e-4f))) continue;
                sum += s.brdf.evaluate(s.normal, s.toViewer, L) * (NoL * cosL * area / (dist * dist));
            }
            total += sum * color * (1.0f / float(mSamples));
            continue;
        }
        Vec3f L;
        float irradiance, maxDist, extent;  // extent: sphere radius or cone half-angle
        if (light.type == LightType::Directional) {
            L = normalize(-Vec3f(light.direction));
            irradiance = 1.0f;
            maxDist = std::numeric_limits<float>::infinity();
            extent = float(light.sourceAngleDegrees * kPi / 360.0);
        } else {
            const Vec3d toLight = (light.position - mScene.origin()) - Vec3d(P);
            const double dist = length(toLight);
            L = Vec3f(toLight / dist);
            irradiance = float(1.0 / (dist * dist));
            maxDist = float(dist);
            extent = light.radius;
            if (light.type == LightType::Spot) {
                // Unreal's spot falloff: saturate((cos − cosOuter)/(cosInner − cosOuter))².
                const float cosOuter = std::cos(light.outerConeDegrees * kPiF / 180.0f);
                const float cosInner = std::cos(light.innerConeDegrees * kPiF / 180.0f);
                const float cosA = dot(-L, normalize(Vec3f(light.direction)));
                const float t = std::clamp((cosA - cosOuter) / std::max(cosInner - cosOuter, 1e-4f),
                                           0.0f, 1.0f);
                irradiance *= t * t;
            }
        }
        const float NoL = dot(s.normal, L);
        if (NoL <= 0.0f || irradiance <= 0.0f) continue;
        const int n = extent > 0.0f ? mSamples : 1;
        Vec3f t, b;
        basis(L, t, b);
        int visible = 0;
        for (int k = 0; k < n; ++k) {
            Vec3f dir = L;
            float tfar = maxDist;
            if (extent > 0.0f) {
                float u, v;
                stratified(k, n, rng, u, v);
                const float r = std::sqrt(u), phi = 2.0f * kPiF * v;
                if (light.type == LightType::Directional) {
                    // A disk of the cone's tangent at unit distance approximates the cone.
                    const float tanA = std::tan(extent);
                    dir = normalize(L + (t * std::cos(phi) + b * std::sin(phi)) * (r * tanA));
                } else {
                    const Vec3f q = L * maxDist + (t * std::cos(phi) + b * std::sin(phi)) * (r * extent);
                    tfar = length(q);
                    dir = q / tfar;
                }
            }
            ++shadowRays;
            if (!mScene.occluded(origin, dir, 0.0f, tfar * (1.0f - 1e-5f))) ++visible;
        }
        if (visible == 0) continue;
        total += s.brdf.evaluate(s.normal, s.toViewer, L) * color *
                 (irradiance * NoL * float(visible) / float(n));
    }
    return total;
}

}  // namespace fp
