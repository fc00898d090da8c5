#include "shading/ReflectionHitWave.h"

#include <algorithm>

namespace fp {

void ReflectionHitWave::light(const ReflectionHitLighting& how, const SurfacePoint* const* hits,
                              Rng* const* rngs, int count, Vec3f* radiance,
                              ReflectionHitWork& work) {
    DiffusePathSetup paths;
    paths.scene = how.scene;
    paths.lighting = how.lighting;
    paths.sky = how.sky ? how.sky->source : nullptr;
    const EmbreeTracer tracer{paths};
    const DirectLighting& lighting = *how.lighting;
    const SH3* skySh = how.sky ? &how.sky->sh : nullptr;
    const int lights = lighting.lightCount();
    // Each light's samples: slots [mLightSlots[l], mLightSlots[l + 1]) of a hit's.
    mLightScale.resize(std::size_t(lights));
    mLightSlots.assign(1, 0);
    for (int l = 0; l < lights; ++l) {
        const int n = samplesOf(lighting.lightView(l), lighting.samples());
        mLightScale[std::size_t(l)] = 1.0f / float(n);
        mLightSlots.push_back(mLightSlots.back() + n);
    }
    mSlots = mLightSlots.back();

    // Every hit's light samples in SIMD lanes of neighbouring hits, then each hit's indirect
    // light, from its own stream in lightReflectionHit's order; each hit's shadow rays in the
    // order drawn.
    mShadowRays.clear();
    mValue.clear();
    mSlot.clear();
    mFirstRay.clear();
    mIndirect.resize(std::size_t(count));
    if (lights > 0) {
        mHitLanes.resize(count);
        for (int i = 0; i < count; ++i) mHitLanes.set(std::size_t(i), *hits[i], rngs[i]->state());
        drawLightRayLanes(lighting.lightViews().data(), lights, lighting.samples(), mHitLanes,
                          mSamples);
    }
    for (int i = 0; i < count; ++i) {
        const std::size_t g = std::size_t(i);
        mFirstRay.push_back(mShadowRays.size());
        if (lights > 0) {
            *rngs[i] = Rng::resume(mHitLanes.rng[g]);
            for (int slot = 0; slot < mSlots; ++slot) {
                const std::size_t at = std::size_t(slot) * std::size_t(mSamples.stride) + g;
                if (!mSamples.keep[at]) continue;
                mShadowRays.push(mHitLanes, g, mSamples, at);
                mSlot.push_back(slot);
                mValue.push_back({mSamples.lr[at], mSamples.lg[at], mSamples.lb[at]});
            }
        }
        mIndirect[g] = reflectionHitIndirect(tracer, *hits[i], skySh, how.indirectBounces,
                                             *rngs[i], work.shadowRays, work.indirectRays);
    }
    mFirstRay.push_back(mShadowRays.size());

    // Their shadow rays, in packets (none traced unshadowed: every sample counts).
    if (how.shadowed) work.shadowRays += mShadowRays.size();
    mShadowRays.trace(*how.scene, how.shadowed);

    // Each hit's lights as shadeLights sums them: a light's unblocked samples in the order
    // drawn, over its sample count.
    for (int i = 0; i < count; ++i) {
        Vec3f total;
        std::size_t r = mFirstRay[std::size_t(i)];
        const std::size_t end = mFirstRay[std::size_t(i) + 1];
        for (int l = 0; l < lights; ++l) {
            Vec3f sum;
            for (; r < end && mSlot[r] < mLightSlots[std::size_t(l) + 1]; ++r)
                if (!mShadowRays.blocked(r)) sum += mValue[r];
            total += sum * mLightScale[std::size_t(l)];
        }
        radiance[i] = reflectionHitRadiance(hits[i]->emission, total, mIndirect[std::size_t(i)]);
    }
}

}  // namespace fp
