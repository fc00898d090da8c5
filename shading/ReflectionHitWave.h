#pragma once
// Reflection hits lit together through Embree's scene (CPU only): every hit's light samples
// drawn in shadeLights' order in SIMD lanes of neighbouring hits (ReflectionHitLanes.h), then
// each hit's indirect light, then every hit's shadow rays in Embree's packets (rtcOccluded16 with
// AVX-512, 8 elsewhere) before each hit sums its unblocked samples light by light as shadeLights
// does. Each hit draws from its own stream in the order
// lightReflectionHit draws, and Embree's packets answer as its single rays do, so each hit ends
// with lightReflectionHit's bits (RTReflectionsTests checks it).
#include "foundation/Random.h"
#include "foundation/Math.h"
#include "shading/DirectLighting.h"
#include "shading/ReflectionHitLanes.h"
#include "shading/ReflectionHits.h"
#include "shading/ShadowRayBatch.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace fp {

class ReflectionHitWave {
public:
    /// radiance[i]: what hit *hits[i] sends back along its ray, lit as `how` says (its light
    /// samples how.lighting's), drawing from *rngs[i]; `work` counts the rays traced.
    void light(const ReflectionHitLighting& how, const SurfacePoint* const* hits,
               Rng* const* rngs, int count, Vec3f* radiance, ReflectionHitWork& work);

private:
    // The hits' shadow rays, in the order drawn, the sample each is (its slot among a hit's
    // samples) and what it adds when unblocked.
    ShadowRayBatch mShadowRays;
    std::vector<int> mSlot;
    std::vector<Vec3f> mValue;
    std::vector<std::size_t> mFirstRay;  // of each hit, into the arrays
    std::vector<Vec3f> mIndirect;        // each hit's indirect light
    std::vector<float> mLightScale;      // 1 / a light's sample count
    std::vector<int> mLightSlots;        // the first sample slot of each light, and the end
    int mSlots = 0;                      // the samples of a hit
    ReflectionHitLanes mHitLanes;        // the hits as the lanes read them
    SampleLanes mSamples;                // and their samples
};

}  // namespace fp
