#include "shading/DirectLighting.h"

#include "foundation/Sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp {

namespace {

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

SurfacePoint surfaceAt(const RayScene& scene, const RayHit& hit, const Vec3f& org, const Vec3f& dir) {
    Vec3f ng = hit.geometricNormal, n = scene.shadingNormal(hit);
    if (dot(ng, dir) > 0.0f) ng = -ng;
    if (dot(n, ng) < 0.0f) n = -n;
    const Material& m = scene.material(hit);
    return {org + dir * hit.t, n, ng, -dir,
            SurfaceBRDF::fromMaterial(m.baseColor, m.metallic, m.specular, m.roughness), m.emission};
}

bool DirectLighting::hasExtent(const Light& light) {
    return light.type == LightType::Rect ||
           (light.type == LightType::Directional && light.sourceAngleDegrees > 0) ||
           (light.type != LightType::Directional && light.radius > 0);
}

LightSample DirectLighting::sample(const Light& light, const SurfacePoint& s, float u, float v) const {
    const Vec3f color = light.color * light.intensity;
    const Vec3f P = s.position;
    LightSample out;
    if (light.type == LightType::Rect) {
        const Vec3f c = Vec3f(light.position - mScene.origin());
        const Vec3f hu = Vec3f(light.halfU), hv = Vec3f(light.halfV);
        const Vec3f nl = normalize(cross(hu, hv));
        const float area = 4.0f * length(cross(hu, hv));
        const Vec3f q = c + hu * (2.0f * u - 1.0f) + hv * (2.0f * v - 1.0f);
        const Vec3f d = q - s.rayOrigin();
        const float dist = length(d);
        out.L = out.shadowDir = d / dist;
        // Stop just short of the emitter so its own quad does not shadow it.
        out.shadowDistance = dist * (1.0f - 1e-4f);
        const float cosL = -dot(out.L, nl);
        if (cosL > 0.0f) out.irradiance = color * (cosL * area / (dist * dist));
        return out;
    }
    float extent;  // sphere radius or cone half-angle
    float maxDist;
    float irradiance;
    if (light.type == LightType::Directional) {
        out.L = normalize(-Vec3f(light.direction));
        irradiance = 1.0f;
        maxDist = std::numeric_limits<float>::infinity();
        extent = float(light.sourceAngleDegrees * kPi / 360.0);
    } else {
        const Vec3d toLight = (light.position - mScene.origin()) - Vec3d(P);
        const double dist = length(toLight);
        out.L = Vec3f(toLight / dist);
        irradiance = float(1.0 / (dist * dist));
        maxDist = float(dist);
        extent = light.radius;
        irradiance *= light.spotMask(dot(-out.L, normalize(Vec3f(light.direction))));
    }
    out.irradiance = color * irradiance;
    out.shadowDir = out.L;
    float tfar = maxDist;
    if (extent > 0.0f) {
        Vec3f t, b;
        orthonormalBasis(out.L, t, b);
        const float r = std::sqrt(u), phi = 2.0f * kPiF * v;
        const Vec3f disk = t * std::cos(phi) + b * std::sin(phi);
        if (light.type == LightType::Directional) {
            // A disk of the cone's tangent at unit distance approximates the cone.
            out.shadowDir = normalize(out.L + disk * (r * std::tan(extent)));
        } else {
            const Vec3f q = out.L * maxDist + disk * (r * extent);
            tfar = length(q);
            out.shadowDir = q / tfar;
        }
    }
    out.shadowDistance = tfar * (1.0f - 1e-5f);
    return out;
}

bool DirectLighting::visible(const SurfacePoint& s, const LightSample& ls) const {
    return !mScene.occluded(s.rayOrigin(), ls.shadowDir, 0.0f, ls.shadowDistance);
}

Vec3f DirectLighting::shade(const SurfacePoint& s, Rng& rng, uint64_t& shadowRays,
                            bool shadowed) const {
    Vec3f total;
    for (const Light& light : mScene.scene().lights) {
        const int n = samplesFor(light);
        Vec3f sum;
        for (int k = 0; k < n; ++k) {
            float u = 0.5f, v = 0.5f;
            if (n > 1 || light.type == LightType::Rect) stratified(k, n, rng, u, v);
            const LightSample ls = sample(light, s, u, v);
            const float NoL = dot(s.normal, ls.L);
            if (NoL <= 0.0f || !ls.reaches()) continue;
            if (shadowed) {
                ++shadowRays;
                if (!visible(s, ls)) continue;
            }
            sum += s.brdf.evaluate(s.normal, s.toViewer, ls.L) * ls.irradiance * NoL;
        }
        total += sum * (1.0f / float(n));
    }
    return total;
}

}  // namespace fp
