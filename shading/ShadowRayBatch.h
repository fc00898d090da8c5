#pragma once
// A wave's shadow rays (DiffusePathWave's and ReflectionHitWave's), gathered in the order their
// samples were drawn and traced together in Embree's packets of neighbours (rtcOccluded16 with
// AVX-512, 8 elsewhere), each answering as its single ray (DirectLighting::visible's) would.
#include "foundation/RayScene.h"
#include "shading/DiffusePathLanes.h"

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

namespace fp {

class ShadowRayBatch {
public:
    void clear() {
        for (auto* v : {&mOrgX, &mOrgY, &mOrgZ, &mDirX, &mDirY, &mDirZ, &mTfar}) v->clear();
    }
    std::size_t size() const { return mTfar.size(); }
    /// The shadow ray of sample `at` of `samples`, from hit `i` of `hits` (its rays' origin).
    void push(const HitLanes& hits, std::size_t i, const SampleLanes& samples, std::size_t at) {
        mOrgX.push_back(hits.ox[i]);
        mOrgY.push_back(hits.oy[i]);
        mOrgZ.push_back(hits.oz[i]);
        mDirX.push_back(samples.dx[at]);
        mDirY.push_back(samples.dy[at]);
        mDirZ.push_back(samples.dz[at]);
        mTfar.push_back(samples.tfar[at]);  // from 0, as DirectLighting::visible's ray
    }
    /// Every ray traced through `scene` (`shadowed` false: none, every ray unblocked); then
    /// blocked(i) says what ray i met.
    void trace(const RayScene& scene, bool shadowed = true) {
        const std::size_t n = size();
        if (mBlockedCapacity < n) {
            mBlockedCapacity = std::max(n, 2 * mBlockedCapacity);
            mBlocked = std::make_unique<bool[]>(mBlockedCapacity);
        }
        if (!shadowed) {
            std::fill_n(mBlocked.get(), n, false);
            return;
        }
        const int width = scene.packetWidth();
        const RayArrays arrays{mOrgX.data(), mOrgY.data(), mOrgZ.data(), mDirX.data(),
                               mDirY.data(), mDirZ.data(), mTfar.data()};
        for (std::size_t r = 0; r < n; r += std::size_t(width))
            scene.occludedPacket(arrays.from(r), int(std::min(n - r, std::size_t(width))), width,
                                 mBlocked.get() + r);
    }
    bool blocked(std::size_t i) const { return mBlocked[i]; }

private:
    std::vector<float> mOrgX, mOrgY, mOrgZ, mDirX, mDirY, mDirZ, mTfar;
    std::unique_ptr<bool[]> mBlocked;
    std::size_t mBlockedCapacity = 0;
};

}  // namespace fp
