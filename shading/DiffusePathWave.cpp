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
        for (auto* v : {&mOrgX, &mOrgY, &mOrgZ, &mDirX, &mDirY, &mDirZ, &mTfar}) v->clear();
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
            for (std::size_t g = 0; g < lit; ++g) {
                const SurfacePoint& s = mHits[std::size_t(mGoing[g])].surface;
                const Vec3f org = s.rayOrigin();
                mHitLanes.px[g] = s.position.x;
                mHitLanes.py[g] = s.position.y;
                mHitLanes.pz[g] = s.position.z;
                mHitLanes.ox[g] = org.x;
                mHitLanes.oy[g] = org.y;
                mHitLanes.oz[g] = org.z;
                mHitLanes.nx[g] = s.normal.x;
                mHitLanes.ny[g] = s.normal.y;
                mHitLanes.nz[g] = s.normal.z;
                mHitLanes.dr[g] = s.brdf.diffuseColor.x;
                mHitLanes.dg[g] = s.brdf.diffuseColor.y;
                mHitLanes.db[g] = s.brdf.diffuseColor.z;
                mHitLanes.rng[g] = rngs[mGoing[g]]->state();
            }
            drawLightSampleLanes(c.lighting->lightViews().data(), lights, c.nee, mHitLanes,
                                 mSamples);
            for (std::size_t g = 0; g < lit; ++g) {
                *rngs[mGoing[g]] = Rng::resume(mHitLanes.rng[g]);
                mFirstShadowRay.push_back(mTfar.size());
                for (int k = 0; k < c.nee; ++k) {
                    const std::size_t at = std::size_t(k) * std::size_t(mSamples.stride) + g;
                    if (!mSamples.keep[at]) continue;
                    mOrgX.push_back(mHitLanes.ox[g]);
                    mOrgY.push_back(mHitLanes.oy[g]);
                    mOrgZ.push_back(mHitLanes.oz[g]);
                    mDirX.push_back(mSamples.dx[at]);
                    mDirY.push_back(mSamples.dy[at]);
                    mDirZ.push_back(mSamples.dz[at]);
                    mTfar.push_back(mSamples.tfar[at]);  // from 0, as DirectLighting::visible's ray
                    mLit.push_back({mSamples.lr[at], mSamples.lg[at], mSamples.lb[at]});
                }
            }
        } else {
            mFirstShadowRay.assign(lit, 0);
        }
        mFirstShadowRay.push_back(mTfar.size());

        // The step's shadow rays, in packets.
        const std::size_t n = mTfar.size();
        shadowRays += n;
        if (mBlockedCapacity < n) {
            mBlockedCapacity = std::max(n, 2 * mBlockedCapacity);
            mBlocked = std::make_unique<bool[]>(mBlockedCapacity);
        }
        const RayArrays arrays{mOrgX.data(), mOrgY.data(), mOrgZ.data(), mDirX.data(),
                               mDirY.data(), mDirZ.data(), mTfar.data()};
        for (std::size_t r = 0; r < n; r += std::size_t(width))
            scene.occludedPacket(arrays.from(r), int(std::min(n - r, std::size_t(width))), width,
                                 mBlocked.get() + r);

        // Each path's light (its unblocked samples summed in the order drawn), then its next
        // bounce.
        std::size_t next = 0;
        for (std::size_t g = 0; g < mGoing.size(); ++g) {
            const int i = mGoing[g];
            Vec3f unblocked;
            for (std::size_t r = mFirstShadowRay[g]; r < mFirstShadowRay[g + 1]; ++r)
                if (!mBlocked[r]) unblocked += mLit[r];
            leaveHit(c, paths[i], mHits[std::size_t(i)].surface,
                     lightEstimate(unblocked, tracer.lightCount(), c.nee), *rngs[i]);
            if (!paths[i].done) mGoing[next++] = i;
        }
        mGoing.resize(next);
    }
}

}  // namespace fp
