#pragma once
// The ray-traceable scene: an Embree 3 BVH over the scene's triangles. Vertices are stored as
// float offsets from `origin` (usually the camera), computed in double, so rays near a camera far
// from the world origin keep full precision (algorithms §1.2–1.3, "translated world"). Every Embree
// call of framepass lives in RayScene.cpp, so moving to Embree 4 touches one file.
#include "foundation/Bvh.h"
#include "foundation/Math.h"
#include "foundation/Scene.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

namespace fp {

struct RayHit {
    bool hit = false;
    float t = 0;
    unsigned mesh = 0, triangle = 0;
    float u = 0, v = 0;  //!< barycentrics of vertices 1 and 2
    Vec3f geometricNormal;  //!< unit, as wound (not facing-corrected)
};

/// A ray for the packet queries: org + t·dir for t in [tnear, tfar], org relative to the origin.
struct Ray {
    Vec3f org, dir;
    float tnear = 0.0f, tfar = 0.0f;
};

/// Where a ray leaving a surface point `p` should start so that it does not meet the surface it
/// leaves: `p` moved along `away` (a vector in front of every surface through p, unit-ish) by a
/// fixed number of float ulps per component, so the step grows with |p| exactly as the rounding
/// error of a computed hit point does (Wächter and Binder, "A Fast and Robust Method for
/// Avoiding Self-Intersection", Ray Tracing Gems ch. 6: 256 ulps, and 2⁻¹⁶ absolute for
/// components within 1/32 of 0, where ulps vanish).
FP_HD inline Vec3f offsetRayOrigin(const Vec3f& p, const Vec3f& away) {
    constexpr float kNearZero = 1.0f / 32.0f, kAbsoluteScale = 1.0f / 65536.0f, kUlps = 256.0f;
    auto offset = [&](float x, float a) {
        if (std::fabs(x) < kNearZero) return x + kAbsoluteScale * a;
        // Adding to the bit pattern moves a positive float away from 0 and a negative one
        // towards it: flip the step's sign with x's so the move follows `away`.
        const int32_t step = int32_t(kUlps * a);
        return std::bit_cast<float>(std::bit_cast<int32_t>(x) + (x < 0.0f ? -step : step));
    };
    return {offset(p.x, away.x), offset(p.y, away.y), offset(p.z, away.z)};
}

/// The widest packet the packet queries take (rtcOccluded16).
constexpr int kMaxPacketSize = 16;

/// Rays as a structure of arrays, as shadow passes build them and Embree's packets take them:
/// ray i runs from (orgX[i], orgY[i], orgZ[i]) along the unit (dirX[i], …) for t in [0, tfar[i]].
struct RayArrays {
    const float *orgX, *orgY, *orgZ, *dirX, *dirY, *dirZ, *tfar;
    /// The arrays from ray `first` on.
    RayArrays from(std::size_t first) const {
        return {orgX + first, orgY + first, orgZ + first, dirX + first,
                dirY + first, dirZ + first, tfar + first};
    }
    Ray at(int i) const {
        return {{orgX[i], orgY[i], orgZ[i]}, {dirX[i], dirY[i], dirZ[i]}, 0.0f, tfar[i]};
    }
};

class RayScene {
public:
    /// Builds the BVH (Embree's high build quality: offline, static geometry).
    RayScene(const Scene& scene, const Vec3d& origin);
    ~RayScene();
    RayScene(const RayScene&) = delete;
    RayScene& operator=(const RayScene&) = delete;

    const Scene& scene() const { return mScene; }
    const Vec3d& origin() const { return mOrigin; }

    /// Closest hit along org + t·dir, t in [tnear, tfar]; org is relative to origin().
    RayHit intersect(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) const;
    /// True when anything blocks org + t·dir for t in [tnear, tfar].
    bool occluded(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) const;

    /// The packet width Embree traces natively on this CPU: 16 where it has AVX-512, else 8.
    int packetWidth() const { return mPacketWidth; }
    /// rtcOccluded8 or rtcOccluded16 (`width` 8 or 16) on rays [0, count) of `rays`, count 1 to
    /// width: occluded[i] for each.
    void occludedPacket(const RayArrays& rays, int count, int width, bool* occluded) const;
    /// Closest hits of rays [0, count) of `rays` (count 1 to width) in one rtcIntersect8 or
    /// rtcIntersect16 packet (`width` 8 or 16), each as intersect() gives it.
    void intersectPacket(const Ray* rays, int count, int width, RayHit* hits) const;
    /// occludedPacket, then each blocked ray's closest hit (rtcIntersect8/16 on the blocked lanes
    /// only, as occluded() then intersect() do one ray at a time): t[i] is the closest-hit
    /// distance of blocked ray i, −1 for an unblocked ray. Unblocked rays, most of a lit frame's,
    /// cost an any-hit traversal only.
    void occludedWithDistancePacket(const RayArrays& rays, int count, int width, bool* occluded,
                                    float* t) const;
    /// Closest hit of the ray on the meshes with this InstanceId only (other geometry is passed
    /// through): the thickness of a pixel's own object along a ray.
    RayHit intersectInstance(const Vec3f& org, const Vec3f& dir, float tnear, float tfar,
                             uint32_t instanceId) const;
    /// The farthest distance from `p` (relative to origin()) to any point of the scene's bounds.
    float farthestDistance(const Vec3f& p) const;

    /// What a log collects: the occlusion rays (and whether any packet also asked for the blocked
    /// rays' closest hits), and apart the rays asked for their closest hit alone (intersect()).
    struct RayLog {
        std::vector<Ray> rays;
        bool closestHits = false;
        std::vector<Ray> closestRays;
    };
    /// While a log is set, every ray of occluded(), occludedPacket(),
    /// occludedWithDistancePacket(), intersect() and intersectPacket() is appended to it, so `bench` can time bare
    /// Embree loops over exactly the rays a pass traced, asking what the pass asked. nullptr stops.
    void setRayLog(RayLog* log) const;

    /// framepass's own BVH of the scene (Bvh.h), built through Embree's rtcBuildBVH on first use
    /// and kept: what the GPU traverses, and the CPU where a pass asks for the GPU's code.
    BvhView bvh() const;
    /// The same tree in GPU memory, uploaded on first use and kept with the scene.
    BvhView deviceBvh() const;

    /// Interpolated vertex normal (or the geometric normal for flat meshes), unit length.
    Vec3f shadingNormal(const RayHit& hit) const;
    const Material& material(const RayHit& hit) const;
    const Mesh& mesh(const RayHit& hit) const { return mScene.meshes[hit.mesh]; }

private:
    const Scene& mScene;
    Vec3d mOrigin;
    void* mDevice = nullptr;  // RTCDevice, kept opaque so passes need no Embree headers
    void* mRtcScene = nullptr;
    Vec3f mBoundsLo, mBoundsHi;  // relative to mOrigin
    int mPacketWidth = 8;
    struct OwnBvh;
    mutable std::mutex mBvhMutex;
    mutable std::unique_ptr<OwnBvh> mBvh;
    mutable std::mutex mLogMutex;
    mutable RayLog* mLog = nullptr;
    void log(const RayArrays& rays, int count, bool closestHits) const;
};

}  // namespace fp
