#pragma once
// Diffuse paths traced together through Embree's scene, a wave at a time (CPU only): each step
// traces the closest hit of every path still going, then every light sample's shadow ray of the
// step, each in Embree's packets of neighbouring paths (rtcIntersect16 and rtcOccluded16 with
// AVX-512, 8 elsewhere): on the glossy room at 1080p the bare packets take 88 % and 48 % of the
// time the same rays take one at a time. The step's light samples run with its hits in SIMD
// lanes (DiffusePathLanes.h). Each path takes traceDiffusePath's own steps (DiffusePaths.h:
// reachHit, drawLightSample, lightEstimate, leaveHit) in its order and draws from its own
// stream, and Embree's packets answer as its single rays do, so a path ends with the bits
// traceDiffusePath gives it (RTGlobalIlluminationTests checks it on every instruction set).
#include "shading/DiffusePathLanes.h"
#include "shading/DiffusePaths.h"
#include "shading/ShadowRayBatch.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace fp {

class DiffusePathWave {
public:
    /// Paths [0, count) of `paths` to their ends through `c`'s scene; path i draws from
    /// *rngs[i]. `rays` and `shadowRays` count what they traced.
    void trace(const DiffusePathSetup& c, PathState* paths, Rng* const* rngs, int count,
               uint64_t& rays, uint64_t& shadowRays);

private:
    std::vector<int> mGoing;       // the paths still going, in order
    std::vector<Ray> mRays;        // each going path's ray this step
    std::vector<RayHit> mRayHits;  // and what Embree found along it
    std::vector<PathHit> mHits;    // each going path's hit this step
    std::vector<std::size_t> mFirstShadowRay;  // of each going path with a hit, into the arrays
    // This step's shadow rays, in the order drawn, and what each adds when unblocked.
    ShadowRayBatch mShadowRays;
    std::vector<Vec3f> mLit;
    HitLanes mHitLanes;       // the step's hits with a light to sample, as the lanes read them
    SampleLanes mSamples;     // and their samples
};

}  // namespace fp
