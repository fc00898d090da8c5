#include "shading/DiffusePathWave.h"

#include <algorithm>

namespace fp {

void DiffusePathWave::trace(const DiffusePathSetup& c, PathState* paths, Rng* const* rngs,
                            int count, uint64_t& rays, uint64_t& shadowRays) {
    const EmbreeTracer tracer{c};
    const RayScene& scene = *c.scene;
    const int width = scene.packetWidth();
    mGoing.clear();
    for (int i = 0; i < count; ++i)
        if (!paths[i].done) mGoing.push_back(i);
    mHits.resize(std::size_t(count));
    while (!mGoing.empty()) {
        // Each going path's closest hit, and the light samples at the hits.
        mShadowRays.clear();
        mLit.clear();
        mFirstShadowRay.clear();
        const std::size_t going = mGoing.size();
        mRays.resize(going);
        mRayHits.resize(going);
        for (std::size_t g = 0; g < going; ++g) {
            const PathState& p = paths[mGoing[g]];
            mRays[g] = {p.org, p.dir, p.tMin, c.reach};
        }
        rays += going;
        for (std::size_t r = 0; r < going; r += std::size_t(width))
            scene.intersectPacket(mRays.data() + r, int(std::min(going - r, std::size_t(width))),
                                  width, mRayHits.data() + r);
        std::size_t lit = 0;
        for (std::size_t g = 0; g < going; ++g) {
            const int i = mGoing[g];
            PathState& p = paths[i];
            PathHit& hit = mHits[std::size_t(i)];
            tracer.fillPathHit(mRayHits[g], p.org, p.dir, hit);
            if (reachHit(tracer, c, p, hit)) mGoing[lit++] = i;
        }
        mGoing.resize(lit);

        // The light samples at the hits, in SIMD lanes of neighbouring hits; each hit's shadow
        // rays in the order drawn.
        const int lights = tracer.lightCount();
        if (lights > 0 && c.nee > 0 && lit > 0) {
            mHitLanes.resize(int(lit));
            for (std::size_t g = 0; g < lit; ++g)
                mHitLanes.set(g, mHits[std::size_t(mGoing[g])].surface, rngs[mGoing[g]]->state());
            drawLightSampleLanes(c.lighting->lightViews().data(), lights, c.nee, mHitLanes,
                                 mSamples);
            for (std::size_t g = 0; g < lit; ++g) {
                *rngs[mGoing[g]] = Rng::resume(mHitLanes.rng[g]);
                mFirstShadowRay.push_back(mShadowRays.size());
                for (int k = 0; k < c.nee; ++k) {
                    const std::size_t at = std::size_t(k) * std::size_t(mSamples.stride) + g;
                    if (!mSamples.keep[at]) continue;
                    mShadowRays.push(mHitLanes, g, mSamples, at);
                    mLit.push_back({mSamples.lr[at], mSamples.lg[at], mSamples.lb[at]});
                }
            }
        } else {
            mFirstShadowRay.assign(lit, 0);
        }
        mFirstShadowRay.push_back(mShadowRays.size());

        // The step's shadow rays, in packets.
        shadowRays += mShadowRays.size();
        mShadowRays.trace(scene);

        // Each path's light (its unblocked samples summed in the order drawn), then its next
        // bounce.
        std::size_t next = 0;
        for (std::size_t g = 0; g < mGoing.size(); ++g) {
            const int i = mGoing[g];
            Vec3f unblocked;
            for (std::size_t r = mFirstShadowRay[g]; r < mFirstShadowRay[g + 1]; ++r)
                if (!mShadowRays.blocked(r)) unblocked += mLit[r];
            leaveHit(c, paths[i], mHits[std::size_t(i)].surface,
                     lightEstimate(unblocked, tracer.lightCount(), c.nee), *rngs[i]);
            if (!paths[i].done) mGoing[next++] = i;
        }
        mGoing.resize(next);
    }
}

}  // namespace fp
