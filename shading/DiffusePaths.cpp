#include "shading/DiffusePaths.h"

#include "foundation/Sampling.h"

#include <algorithm>

namespace fp {

namespace {

// The diffuse light the lights send to hit `s`: each of `nee` samples picks one light uniformly
// and traces its shadow ray; the sum is scaled by the light count over the sample count (the
// pick's pdf).
Vec3f sampleLights(const DiffusePathSetup& c, const SurfacePoint& s, Rng& rng, uint64_t& shadowRays) {
    const int n = int(c.lights->size());
    Vec3f sum;
    if (n == 0 || c.nee <= 0) return sum;
    for (int k = 0; k < c.nee; ++k) {
        const float pick = rng.nextFloat(), u = rng.nextFloat(), v = rng.nextFloat();
        const Light& light = (*c.lights)[std::min(int(pick * float(n)), n - 1)];
        const LightSample ls = c.lighting->sample(light, s, u, v);
        const float cosine = dot(s.normal, ls.L);
        if (!ls.reaches() || cosine <= 0.0f) continue;
        ++shadowRays;
        if (!c.lighting->visible(s, ls)) continue;
        sum += s.brdf.diffuseColor * ls.irradiance * (cosine / kPiF);
    }
    return sum * (float(n) / float(c.nee));
}

}  // namespace

DiffusePath traceDiffusePath(const DiffusePathSetup& c, Vec3f org, Vec3f dir, float tMin, Rng& rng,
                             uint64_t& rays, uint64_t& shadowRays) {
    DiffusePath out;
    Vec3f throughput{1, 1, 1};
    const float reach = c.reach;  // every ray of the path, as Unreal reuses its ray description
    for (int bounce = 0; bounce < c.bounces; ++bounce) {
        ++rays;
        const RayHit hit = c.scene->intersect(org, dir, tMin, reach);
        if (!hit.hit) {
            // The first ray's sky is the sky light's own diffuse term, another pass's.
            if (c.sky && (bounce > 0 || c.skyOnFirstRay)) out.radiance += throughput * c.sky->radiance(dir);
            return out;
        }
        if (bounce == 0) {
            out.firstHit = hit.t;
            if (hit.t > c.giDistance) return out;
        }
        const SurfacePoint s = surfaceAt(*c.scene, hit, org, dir);
        // No emission at hits unless asked: Unreal adds only the lights' light (and no lightmap).
        if (c.emissionAtHits)
            out.radiance += throughput * c.scene->scene().emissionTowardsSurfaces(hit.mesh);
        out.radiance += throughput * sampleLights(c, s, rng, shadowRays);
        if (bounce + 1 == c.bounces) return out;
        // The next diffuse bounce: BxDF·cos/pdf = DiffuseColor.
        const float u = rng.nextFloat(), v = rng.nextFloat();
        dir = cosineHemisphere(s.normal, u, v);
        org = s.rayOrigin();
        tMin = 0.0f;
        throughput = throughput * s.brdf.diffuseColor;
    }
    return out;
}

}  // namespace fp
