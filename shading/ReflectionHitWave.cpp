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
    mLightScale.resize(std::size_t(lights));
    for (int l = 0; l < lights; ++l)
        mLightScale[std::size_t(l)] =
            1.0f / float(lighting.lightView(l).hasExtent() ? lighting.samples() : 1);

    // Each hit's light samples, then its indirect light, from its own stream in
    // lightReflectionHit's order.
    for (auto* v : {&mOrgX, &mOrgY, &mOrgZ, &mDirX, &mDirY, &mDirZ, &mTfar}) v->clear();
    mLight.clear();
    mValue.clear();
    mFirstRay.clear();
    mIndirect.resize(std::size_t(count));
    for (int i = 0; i < count; ++i) {
        const SurfacePoint& s = *hits[i];
        const Vec3f org = s.rayOrigin();
        int light = 0;
        mFirstRay.push_back(mTfar.size());
        drawLightRays(
            tracer, lighting.samples(), s, *rngs[i],
            [&](const LightSample& ls, float NoL) {
                mOrgX.push_back(org.x);
                mOrgY.push_back(org.y);
                mOrgZ.push_back(org.z);
                mDirX.push_back(ls.shadowDir.x);
                mDirY.push_back(ls.shadowDir.y);
                mDirZ.push_back(ls.shadowDir.z);
                mTfar.push_back(ls.shadowDistance);  // from 0, as DirectLighting::visible's ray
                mLight.push_back(light);
                mValue.push_back(lightValue(s, ls, NoL));
            },
            [&](int) { ++light; });
        mIndirect[std::size_t(i)] = reflectionHitIndirect(tracer, s, skySh, how.indirectBounces,
                                                          *rngs[i], work.shadowRays,
                                                          work.indirectRays);
    }
    mFirstRay.push_back(mTfar.size());

    // Their shadow rays, in packets (none traced unshadowed: every sample counts).
    const std::size_t n = mTfar.size();
    if (mBlockedCapacity < n) {
        mBlockedCapacity = std::max(n, 2 * mBlockedCapacity);
        mBlocked = std::make_unique<bool[]>(mBlockedCapacity);
    }
    if (how.shadowed) {
        work.shadowRays += n;
        const RayScene& scene = *how.scene;
        const int width = scene.packetWidth();
        const RayArrays arrays{mOrgX.data(), mOrgY.data(), mOrgZ.data(), mDirX.data(),
                               mDirY.data(), mDirZ.data(), mTfar.data()};
        for (std::size_t r = 0; r < n; r += std::size_t(width))
            scene.occludedPacket(arrays.from(r), int(std::min(n - r, std::size_t(width))), width,
                                 mBlocked.get() + r);
    } else {
        std::fill_n(mBlocked.get(), n, false);
    }

    // Each hit's lights as shadeLights sums them: a light's unblocked samples in the order
    // drawn, over its sample count.
    for (int i = 0; i < count; ++i) {
        Vec3f total;
        std::size_t r = mFirstRay[std::size_t(i)];
        const std::size_t end = mFirstRay[std::size_t(i) + 1];
        for (int l = 0; l < lights; ++l) {
            Vec3f sum;
            for (; r < end && mLight[r] == l; ++r)
                if (!mBlocked[r]) sum += mValue[r];
            total += sum * mLightScale[std::size_t(l)];
        }
        radiance[i] = reflectionHitRadiance(hits[i]->emission, total, mIndirect[std::size_t(i)]);
    }
}

}  // namespace fp
