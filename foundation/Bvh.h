#pragma once
// framepass's own bounding volume hierarchy: the layout the GPU traverses, and the traversal,
// written once as FP_HD so the CPU can run the GPU's exact code (rt_shadows' `traversal: "bvh"`).
// Embree builds the tree on the host (RayScene::bvh(), through rtcBuildBVH with nodes of our
// layout); the GPU gets a copy once per scene (RayScene::deviceBvh()).
//
// A binary tree whose nodes hold both children's boxes (Aila and Laine, "Understanding the
// Efficiency of Ray Traversal on GPUs", 2009: one node fetch tests two boxes), leaves of up to
// four triangles stored in order, and a watertight ray–triangle test (Woop, Benthin and Wald,
// "Watertight Ray/Triangle Intersection", JCGT 2013), so a ray through a shared edge or vertex of
// a closed mesh always hits one of its triangles, as Embree's robust mode promises. The box test
// widens each slab interval by 2·γ₃ (Ize, "Robust BVH Ray Traversal", JCGT 2013) so rounding
// never culls a box the ray touches. Embree's triangle test is another algorithm: a ray whose hit
// lies within rounding of a triangle's edge may decide differently (docs/gpu.md counts them).
#include "foundation/HostDevice.h"
#include "foundation/Math.h"

#include <cmath>
#include <cstdint>

namespace fp {

/// One inner node: both children's boxes and where each child is. A child with count > 0 is a
/// leaf of triangles [child, child + count); count == 0: the inner node `child`; count < 0: none.
struct alignas(16) BvhNode {
    Vec3f lo[2], hi[2];
    int32_t child[2];
    int32_t count[2];
};
static_assert(sizeof(BvhNode) == 64, "a node is one 64-byte fetch");

/// A triangle of a leaf, its vertices relative to the scene's ray origin, and the InstanceId of
/// its mesh (for rays restricted to one object); three 16-byte fetches.
struct alignas(16) BvhTriangle {
    Vec3f v0;
    uint32_t instanceId;
    Vec3f v1;
    uint32_t unused0;
    Vec3f v2;
    uint32_t unused1;
};
static_assert(sizeof(BvhTriangle) == 48, "a triangle is three 16-byte fetches");

/// What shading a hit of a leaf's triangle reads, beside it in leaf order: its vertex normals
/// (smooth = 0: a mesh without normals, shaded by the geometric normal), its material, and
/// whether its mesh is a light's visible shape (which sends no emission to other surfaces: the
/// light delivers its light).
struct alignas(16) BvhShading {
    Vec3f n0;
    uint32_t material;
    Vec3f n1;
    uint32_t smooth;
    Vec3f n2;
    uint32_t lightShape;
};
static_assert(sizeof(BvhShading) == 48, "three 16-byte fetches");

/// A material as a hit's shading reads it (of the scene's Material).
struct BvhMaterial {
    Vec3f baseColor;
    float metallic, specular, roughness;
    Vec3f emission;
};

/// The tree as the traversal reads it, in host or device memory. nodeCount 0: no geometry.
struct BvhView {
    const BvhNode* nodes = nullptr;
    const BvhTriangle* triangles = nullptr;
    int nodeCount = 0;
    Vec3f lo, hi;  //!< the scene's bounds (RayScene's)
    const BvhShading* shading = nullptr;     //!< one a triangle, in the triangles' order
    const BvhMaterial* materials = nullptr;  //!< the scene's, by BvhShading::material
};

/// A closest hit: its distance and the index of its triangle in BvhView::triangles (−1, −1: none).
struct BvhHit {
    float t = -1.0f;
    int triangle = -1;
    FP_HD bool hit() const { return triangle >= 0; }
};

/// Most nodes a path from the root may pass: the build's depth limit, and the traversal's stack.
constexpr int kBvhMaxDepth = 64;

namespace bvh_detail {

/// The ray in the watertight test's sheared frame: kz the axis of the direction's largest
/// component, kx and ky the others in the order that keeps the winding.
struct ShearedRay {
    int kx, ky, kz;
    float sx, sy, sz;
};

FP_HD inline float component(const Vec3f& v, int axis) {
    return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}

FP_HD inline ShearedRay shear(const Vec3f& dir) {
    const float ax = std::fabs(dir.x), ay = std::fabs(dir.y), az = std::fabs(dir.z);
    ShearedRay r;
    r.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    r.kx = r.kz == 2 ? 0 : r.kz + 1;
    r.ky = r.kx == 2 ? 0 : r.kx + 1;
    if (component(dir, r.kz) < 0.0f) {
        const int k = r.kx;
        r.kx = r.ky;
        r.ky = k;
    }
    const float dz = component(dir, r.kz);
    r.sx = component(dir, r.kx) / dz;
    r.sy = component(dir, r.ky) / dz;
    r.sz = 1.0f / dz;
    return r;
}

/// The watertight test's scaled barycentrics of the ray's crossing of the triangle's plane —
/// U, V, W the weights of v0, v1, v2 times their sum — and the hit's scaled distance T.
struct TriangleWeights {
    float U, V, W, T;
};
FP_HD inline TriangleWeights triangleWeights(const ShearedRay& r, const Vec3f& org,
                                             const BvhTriangle& tri) {
    const Vec3f A = tri.v0 - org, B = tri.v1 - org, C = tri.v2 - org;
    const float az = component(A, r.kz), bz = component(B, r.kz), cz = component(C, r.kz);
    const float ax = component(A, r.kx) - r.sx * az, ay = component(A, r.ky) - r.sy * az;
    const float bx = component(B, r.kx) - r.sx * bz, by = component(B, r.ky) - r.sy * bz;
    const float cx = component(C, r.kx) - r.sx * cz, cy = component(C, r.ky) - r.sy * cz;
    float U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        // An edge through the ray: decide it in double, as the paper does, so neighbours agree.
        U = float(double(cx) * double(by) - double(cy) * double(bx));
        V = float(double(ax) * double(cy) - double(ay) * double(cx));
        W = float(double(bx) * double(ay) - double(by) * double(ax));
    }
    return {U, V, W, U * (r.sz * az) + V * (r.sz * bz) + W * (r.sz * cz)};
}

/// The distance t ∈ [tnear, tfar] at which the ray from `org` meets the triangle, or −1.
FP_HD inline float hitTriangle(const ShearedRay& r, const Vec3f& org, const BvhTriangle& tri,
                               float tnear, float tfar) {
    const TriangleWeights w = triangleWeights(r, org, tri);
    const float U = w.U, V = w.V, W = w.W;
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return -1.0f;
    const float det = U + V + W;
    if (det == 0.0f) return -1.0f;
    const float t = w.T / det;
    return t >= tnear && t <= tfar ? t : -1.0f;
}

/// Narrows [enter, leave] to one axis's slab. A NaN bound (0·∞: the ray runs in the slab's
/// boundary plane, so it is inside) leaves the interval as it was: comparisons with NaN are false.
FP_HD inline void clipSlab(float lo, float hi, float o, float inv, float& enter, float& leave) {
    float t0 = (lo - o) * inv, t1 = (hi - o) * inv;
    if (t0 > t1) {
        const float t = t0;
        t0 = t1;
        t1 = t;
    }
    enter = t0 > enter ? t0 : enter;
    leave = t1 < leave ? t1 : leave;
}

/// 1 + 2·γ₃: how far a box's exit distance is widened against rounding.
constexpr float kWiden = 1.0f + 2.0f * 3.0f * 5.9604645e-8f / (1.0f - 3.0f * 5.9604645e-8f);

/// Whether the ray meets the box within [tnear, tfar], the exit widened by 2·γ₃; `enter` is
/// where it enters.
FP_HD inline bool hitBox(const Vec3f& lo, const Vec3f& hi, const Vec3f& org, const Vec3f& inv,
                         float tnear, float tfar, float& enter) {
    enter = tnear;
    float leave = tfar;
    clipSlab(lo.x, hi.x, org.x, inv.x, enter, leave);
    clipSlab(lo.y, hi.y, org.y, inv.y, enter, leave);
    clipSlab(lo.z, hi.z, org.z, inv.z, enter, leave);
    return enter <= leave * kWiden;
}

/// A node or a triangle read whole: on the GPU as 16-byte read-only fetches (a node in four, a
/// triangle in three), where element by element would take a load per float.
FP_HD inline BvhNode loadNode(const BvhNode* p) {
#if defined(__CUDA_ARCH__)
    const float4* q = reinterpret_cast<const float4*>(p);
    const float4 a = __ldg(q), b = __ldg(q + 1), c = __ldg(q + 2), d = __ldg(q + 3);
    BvhNode n;
    n.lo[0] = {a.x, a.y, a.z};
    n.lo[1] = {a.w, b.x, b.y};
    n.hi[0] = {b.z, b.w, c.x};
    n.hi[1] = {c.y, c.z, c.w};
    n.child[0] = __float_as_int(d.x);
    n.child[1] = __float_as_int(d.y);
    n.count[0] = __float_as_int(d.z);
    n.count[1] = __float_as_int(d.w);
    return n;
#else
    return *p;
#endif
}
FP_HD inline BvhTriangle loadTriangle(const BvhTriangle* p) {
#if defined(__CUDA_ARCH__)
    const float4* q = reinterpret_cast<const float4*>(p);
    const float4 a = __ldg(q), b = __ldg(q + 1), c = __ldg(q + 2);
    BvhTriangle t;
    t.v0 = {a.x, a.y, a.z};
    t.instanceId = uint32_t(__float_as_int(a.w));
    t.v1 = {b.x, b.y, b.z};
    t.v2 = {c.x, c.y, c.z};
    return t;
#else
    return *p;
#endif
}

}  // namespace bvh_detail

/// What a query asks: any blocker (a shadow ray), or the closest hit (of one instance, or all).
struct BvhQuery {
    bool anyHit = false;
    bool oneInstance = false;
    uint32_t instanceId = 0;  //!< with oneInstance: only this InstanceId's triangles count
};

// On the GPU the traversal is one function of its own rather than inlined into each pass's kernel
// (rt_shadows calls it three times): its loop keeps its registers, where inlined into a large
// kernel it spilled to memory on every step (204 bytes; the bare traversal kernel spills none).
#if defined(__CUDA_ARCH__)
#define FP_BVH_NOINLINE __noinline__
#else
#define FP_BVH_NOINLINE
#endif

/// The distance of the hit the query asks for along org + t·dir, t ∈ [tnear, tfar] (dir need
/// not be unit), or −1 when there is none. An any-hit query returns the first hit it finds. The
/// nearer child is visited first and a stacked one is dropped once a hit is nearer than where the
/// ray enters it; neither changes the result (the closest of the triangle tests' distances, each
/// computed the same whatever the order), only how much is read.
FP_HD FP_BVH_NOINLINE inline BvhHit traceBvhHit(const BvhView bvh, const Vec3f org,
                                                const Vec3f dir, float tnear, float tfar,
                                                const BvhQuery q) {
    using namespace bvh_detail;
    if (bvh.nodeCount == 0 || !(tnear <= tfar)) return {};
    const ShearedRay sheared = shear(dir);
    const Vec3f inv{1.0f / dir.x, 1.0f / dir.y, 1.0f / dir.z};
    BvhHit best;
    int stackNode[kBvhMaxDepth];
    float stackEnter[kBvhMaxDepth];
    int depth = 0, node = 0;
    for (;;) {
        const BvhNode n = loadNode(bvh.nodes + node);
        float enter[2];
        bool inner[2];
        for (int c = 0; c < 2; ++c) {
            inner[c] = false;
            if (n.count[c] < 0 || !hitBox(n.lo[c], n.hi[c], org, inv, tnear, tfar, enter[c]))
                continue;
            if (n.count[c] == 0) {
                inner[c] = true;
                continue;
            }
            for (int i = n.child[c], end = n.child[c] + n.count[c]; i < end; ++i) {
                const BvhTriangle tri = loadTriangle(bvh.triangles + i);
                if (q.oneInstance && tri.instanceId != q.instanceId) continue;
                const float t = hitTriangle(sheared, org, tri, tnear, tfar);
                if (t < 0.0f) continue;
                if (q.anyHit) return {t, i};
                best = {t, i};
                tfar = t;  // nearer hits only from here on
            }
        }
        if (inner[0] && inner[1]) {
            const bool firstNear = enter[0] <= enter[1];
            stackNode[depth] = firstNear ? n.child[1] : n.child[0];
            stackEnter[depth] = firstNear ? enter[1] : enter[0];
            ++depth;
            node = firstNear ? n.child[0] : n.child[1];
            continue;
        }
        if (inner[0] || inner[1]) {
            node = inner[0] ? n.child[0] : n.child[1];
            continue;
        }
        for (;;) {
            if (depth == 0) return best;
            --depth;
            if (stackEnter[depth] <= tfar * kWiden) break;  // else: wholly beyond a nearer hit
        }
        node = stackNode[depth];
    }
}

/// traceBvhHit's distance alone (−1: no hit).
FP_HD inline float traceBvh(const BvhView bvh, const Vec3f org, const Vec3f dir, float tnear,
                            float tfar, const BvhQuery q) {
    return traceBvhHit(bvh, org, dir, tnear, tfar, q).t;
}

/// A shadow or occlusion ray's blocker: its distance, −1 when nothing blocks the ray — the closest
/// blocker's where `closest` is asked, else the first found (an any-hit query). A ray has a
/// closest hit exactly when it has any, so where the occluder's distance is read this one query
/// answers whether the ray is blocked too, where an any-hit query and then a closest-hit one would
/// traverse a blocked ray twice.
FP_HD inline float traceBlocker(const BvhView bvh, const Vec3f org, const Vec3f dir, float tnear,
                                float tfar, bool closest) {
    return traceBvh(bvh, org, dir, tnear, tfar, closest ? BvhQuery{} : BvhQuery{true, false, 0});
}

/// Where a closest hit lies on its triangle: the barycentric weights (u, v) of v1 and v2 (v0's is
/// 1 − u − v), as the traversal's own triangle test computes them.
FP_HD inline void hitBarycentrics(const BvhView& bvh, const BvhHit& hit, const Vec3f& org,
                                  const Vec3f& dir, float& u, float& v) {
    using namespace bvh_detail;
    const TriangleWeights w =
        triangleWeights(shear(dir), org, loadTriangle(bvh.triangles + hit.triangle));
    const float det = w.U + w.V + w.W;
    u = w.V / det;
    v = w.W / det;
}

/// A hit's shading normal: the vertex normals weighted by its barycentrics (u, v of n1, n2),
/// normalised, or `fallback` (the geometric normal) where they cancel — RayScene's rule for
/// Embree's hits and the BVH's alike.
FP_HD inline Vec3f interpolatedNormal(const Vec3f& n0, const Vec3f& n1, const Vec3f& n2, float u,
                                      float v, const Vec3f& fallback) {
    const Vec3f n = normalize(n0 * (1.0f - u - v) + n1 * u + n2 * v);
    return length(n) > 0.5f ? n : fallback;
}

/// The farthest distance from `p` to any point of the box [lo, hi]: how far a ray from `p` can
/// travel inside a scene of those bounds (RayScene::farthestDistance and the GPU's alike).
FP_HD inline float farthestDistance(const Vec3f& lo, const Vec3f& hi, const Vec3f& p) {
    const float dx = fmaxf(std::fabs(p.x - lo.x), std::fabs(hi.x - p.x));
    const float dy = fmaxf(std::fabs(p.y - lo.y), std::fabs(hi.y - p.y));
    const float dz = fmaxf(std::fabs(p.z - lo.z), std::fabs(hi.z - p.z));
    return length(Vec3f{dx, dy, dz});
}

}  // namespace fp
