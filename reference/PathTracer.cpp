#include "reference/PathTracer.h"

#include "foundation/Sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}

float PathTracer::lobeHitWeight(const RayHit& hit, const Vec3f& dir, float lobePdf) const {
    const float cosL = std::abs(dot(hit.geometricNormal, dir));
    const float areaPdf = mEmitters.pdfArea(hit.mesh);
    if (!(areaPdf > 0.0f) || !(cosL > 0.0f)) return 1.0f;
    const float lightPdf = areaPdf * hit.t * hit.t / cosL;
    return lobePdf / (lobePdf + lightPdf);
}

Vec3f PathTracer::sampleEmitters(const SurfacePoint& s, const ScatterLobe& lobe, Rng& rng,
                                 uint64_t& rays) const {
    if (mEmitters.empty()) return {};
    const float c = rng.nextFloat(), u = rng.nextFloat(), v = rng.nextFloat();
    const EmitterPoint e = mEmitters.sample(c, u, v);
    const Vec3f org = s.rayOrigin();
    const Vec3f d = e.position - org;
    const float dist = length(d);
    if (!(dist > 0.0f)) return {};
    const Vec3f L = d / dist;
    const float cosL = std::abs(dot(L, e.normal));
    const LobeValue lv = lobe.evaluate(L);
    if (!(cosL > 0.0f) || lv.weight.x + lv.weight.y + lv.weight.z <= 0.0f) return {};
    ++rays;
    // Visible when the first thing the ray meets is the emitter's mesh at the sampled distance.
    const RayHit h = mScene.intersect(org, L, 0.0f, dist * (1.0f + 1e-3f));
    if (!h.hit || h.mesh != e.mesh || h.t < dist * (1.0f - 1e-3f)) return {};
    const float lightPdf = e.pdfArea * dist * dist / cosL;
    return e.emission * lv.weight * (1.0f / (lightPdf + lv.pdf));  // (g/p_light)·p_light/(p_light+p_lobe)
}

Vec3f PathTracer::reflectedIndirect(const SurfacePoint& start, Rng& rng, uint64_t& rays) const {
    Vec3f total, beta{1, 1, 1};
    SurfacePoint s = start;
    for (int bounce = 1; bounce <= mMaxBounces; ++bounce) {
        const ScatterLobe lobe(ScatterLobe::Kind::Bsdf, s);
        if (!lobe.active()) break;
        total += beta * sampleEmitters(s, lobe, rng, rays);
        const float c = rng.nextFloat(), u = rng.nextFloat(), v = rng.nextFloat();
        Vec3f dir;
        if (!lobe.sample(c, u, v, dir)) break;
        const LobeValue lv = lobe.evaluate(dir);
        if (!(lv.pdf > 0.0f)) break;
        beta = beta * lv.weight * (1.0f / lv.pdf);
        if (bounce > 2) {
            // Russian roulette: survive with q, divide by q, so the expectation is unchanged.
            const float q = std::min(1.0f, std::max({beta.x, beta.y, beta.z}));
            if (!(q > 0.0f) || rng.nextFloat() >= q) break;
            beta = beta / q;
        }
        const Vec3f org = s.rayOrigin();
        ++rays;
        const RayHit hit = mScene.intersect(org, dir, 0.0f, kInf);
        if (!hit.hit) {  // the sky light's radiance, found by the lobe alone (no MIS partner)
            total += beta * mSky.radiance(dir);
            break;
        }
        const SurfacePoint next = surfaceAt(mScene, hit, org, dir);
        total += beta * (mScene.scene().emissionTowardsSurfaces(hit.mesh) * lobeHitWeight(hit, dir, lv.pdf) +
                         mLighting.shade(next, rng, rays));
        s = next;
    }
    return total;
}

Gathered PathTracer::gather(const SurfacePoint& s, ScatterLobe::Kind kind, Rng& rng,
                            uint64_t& rays) const {
    Gathered out;
    const ScatterLobe lobe(kind, s);
    // Draw every random number of this sample up front, so a sample that ends early leaves the
    // stream of the next one where it would be anyway.
    const float c = rng.nextFloat(), u = rng.nextFloat(), v = rng.nextFloat();
    if (!lobe.active()) return out;
    const Vec3f emitted = sampleEmitters(s, lobe, rng, rays);
    out.oneBounce = out.full = emitted;
    Vec3f dir;
    if (!lobe.sample(c, u, v, dir)) return out;
    const LobeValue lv = lobe.evaluate(dir);
    if (!(lv.pdf > 0.0f)) return out;
    out.sampled = true;
    const Vec3f org = s.rayOrigin();
    ++rays;
    const RayHit hit = mScene.intersect(org, dir, 0.0f, kInf);
    const Vec3f weight = lv.weight * (1.0f / lv.pdf);
    if (!hit.hit) {
        // The sky is direct light: it belongs to the one-bounce layer as well as the full one.
        const Vec3f sky = weight * mSky.radiance(dir);
        out.oneBounce += sky;
        out.full += sky;
        return out;
    }
    out.hit = true;
    out.distance = hit.t;
    out.mesh = int(hit.mesh);
    const SurfacePoint next = surfaceAt(mScene, hit, org, dir);
    const Vec3f atHit =
        mScene.scene().emissionTowardsSurfaces(hit.mesh) * lobeHitWeight(hit, dir, lv.pdf) +
        mLighting.shade(next, rng, rays);
    out.oneBounce += weight * atHit;
    out.full += weight * (atHit + reflectedIndirect(next, rng, rays));
    return out;
}

}  // namespace fp
