// framepass's own BVH (the GPU's) against Embree on the same scene and rays: the tree holds every
// triangle once, hits and misses agree but within rounding of an edge, closest hits agree to the
// rounding of two triangle tests, and a closed mesh has no cracks.
#include "foundation/Bvh.h"
#include "foundation/Random.h"
#include "foundation/RayScene.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <set>

using namespace fp;

TEST_SUITE("bvh") {

namespace {
// A floor, a UV sphere (instance 2) and 400 random triangles (instance 3) in a 200-unit box.
Scene clutteredScene() {
    Scene s = test::sphereOverFloor({}, test::sun({0, -1, 0}));
    Mesh soup;
    soup.instanceId = 3;
    Rng rng(1, 0, 0, 7);
    auto coordinate = [&] { return double(rng.nextFloat()) * 200.0 - 100.0; };
    for (int t = 0; t < 400; ++t) {
        const Vec3d c{coordinate(), std::fabs(coordinate()) * 0.5, coordinate()};
        for (int k = 0; k < 3; ++k) {
            soup.positions.push_back(
                c + Vec3d{coordinate(), coordinate(), coordinate()} * 0.08);
            soup.indices.push_back(uint32_t(3 * t + k));
        }
    }
    s.meshes.push_back(soup);
    return s;
}

Vec3f randomDirection(Rng& rng) {
    for (;;) {
        const Vec3f d{2.0f * rng.nextFloat() - 1.0f, 2.0f * rng.nextFloat() - 1.0f,
                      2.0f * rng.nextFloat() - 1.0f};
        const float l = length(d);
        if (l > 0.1f && l <= 1.0f) return d / l;
    }
}
}  // namespace

TEST_CASE("the tree holds every triangle once, inside its parents' boxes") {
    const Scene scene = clutteredScene();
    const RayScene rs(scene, {5, 7, -3});
    const BvhView bvh = rs.bvh();
    std::size_t triangles = 0;
    for (const Mesh& m : scene.meshes) triangles += m.indices.size() / 3;
    REQUIRE(bvh.nodeCount > 1);
    std::size_t seen = 0, outside = 0;
    std::set<int> reached = {0};
    for (int n = 0; n < bvh.nodeCount; ++n) {
        const BvhNode& node = bvh.nodes[n];
        for (int c = 0; c < 2; ++c) {
            if (node.count[c] < 0) continue;
            if (node.count[c] == 0) {
                CHECK(node.child[c] > n);  // depth first: children after their parent
                reached.insert(node.child[c]);
                continue;
            }
            CHECK(node.count[c] <= 4);
            seen += std::size_t(node.count[c]);
            for (int i = node.child[c]; i < node.child[c] + node.count[c]; ++i)
                for (const Vec3f& v : {bvh.triangles[i].v0, bvh.triangles[i].v1, bvh.triangles[i].v2})
                    for (int a = 0; a < 3; ++a)
                        outside += v[a] < node.lo[c][a] || v[a] > node.hi[c][a];
        }
    }
    CHECK(seen == triangles);
    CHECK(outside == 0);
    CHECK(int(reached.size()) == bvh.nodeCount);  // every node is some node's child
}

TEST_CASE("hits, misses and closest distances agree with Embree's on 200k random rays") {
    const Scene scene = clutteredScene();
    const RayScene rs(scene, {5, 7, -3});
    const BvhView bvh = rs.bvh();
    Rng rng(1, 2, 3, 11);
    const int kRays = 200000;
    int hits = 0, occlusionMismatch = 0, closestMismatch = 0, instanceMismatch = 0;
    double worstRel = 0.0;
    for (int i = 0; i < kRays; ++i) {
        const Vec3f org{rng.nextFloat() * 240.0f - 120.0f, rng.nextFloat() * 80.0f,
                        rng.nextFloat() * 240.0f - 120.0f};
        const Vec3f dir = randomDirection(rng);
        const float tfar = rng.nextFloat() * 300.0f;
        const bool embreeBlocked = rs.occluded(org, dir, 0.0f, tfar);
        const bool bvhBlocked = traceBvh(bvh, org, dir, 0.0f, tfar, {true, false, 0}) >= 0.0f;
        occlusionMismatch += embreeBlocked != bvhBlocked;
        const RayHit h = rs.intersect(org, dir, 0.0f, tfar);
        const float t = traceBvh(bvh, org, dir, 0.0f, tfar, {});
        if (h.hit != (t >= 0.0f)) {
            ++closestMismatch;
        } else if (h.hit) {
            ++hits;
            worstRel = std::max(worstRel, std::fabs(double(t) - h.t) / std::max(double(h.t), 1.0));
        }
        const uint32_t id = 1 + uint32_t(i % 3);
        const RayHit hi = rs.intersectInstance(org, dir, 0.0f, tfar, id);
        const float ti = traceBvh(bvh, org, dir, 0.0f, tfar, {false, true, id});
        instanceMismatch += hi.hit != (ti >= 0.0f);
    }
    // Embree's triangle test and the watertight one round differently: a ray that passes within
    // a few float steps (about 10⁻⁵ units here) of an edge may count as a hit in one and a miss in
    // the other. Random rays meet such a sliver with a probability of order 10⁻⁵ per edge
    // crossing; 20 of 200k (10⁻⁴) leaves room for the scene's thousands of edges.
    CHECK(hits > 20000);
    CHECK(occlusionMismatch <= 20);
    CHECK(closestMismatch <= 20);
    CHECK(instanceMismatch <= 20);
    // Both distances are the exact one within a few float steps of the coordinates (≤ 300 units
    // here, a step 3·10⁻⁵): relative to max(t, 1) that is below 10⁻⁶ apart; 10⁻⁵ for the sum.
    CHECK(worstRel <= 1e-5);
    MESSAGE("mismatches: occluded " << occlusionMismatch << ", closest " << closestMismatch
                                    << ", one instance " << instanceMismatch
                                    << "; worst relative distance " << worstRel);
}

TEST_CASE("traceBlocker: one closest-hit query answers the any-hit query's blocked and the closest distance") {
    // The passes read the occluder's distance from one query (rt_shadows, rt_ambient_occlusion):
    // the same answers as an any-hit query followed, for a blocked ray, by a closest-hit one.
    const Scene scene = clutteredScene();
    const RayScene rs(scene, {5, 7, -3});
    const BvhView bvh = rs.bvh();
    Rng rng(4, 5, 6, 7);
    int blocked = 0, differing = 0;
    for (int i = 0; i < 50000; ++i) {
        const Vec3f org{rng.nextFloat() * 240.0f - 120.0f, rng.nextFloat() * 80.0f,
                        rng.nextFloat() * 240.0f - 120.0f};
        const Vec3f dir = randomDirection(rng);
        const float tfar = rng.nextFloat() * 300.0f;
        const bool anyHit = traceBvh(bvh, org, dir, 0.0f, tfar, {true, false, 0}) >= 0.0f;
        const float first = traceBlocker(bvh, org, dir, 0.0f, tfar, false);
        const float t = traceBlocker(bvh, org, dir, 0.0f, tfar, true);
        blocked += anyHit;
        // Blocked exactly when the any-hit query says so, the closest blocker no farther than the
        // first one found, both within the ray.
        differing += (t >= 0.0f) != anyHit || (first >= 0.0f) != anyHit ||
                     (anyHit && (t > first || first > tfar));
    }
    CHECK(blocked > 5000);  // not vacuous: a tenth of the rays are blocked
    CHECK(differing == 0);
}

TEST_CASE("Embree's closest-hit packets give each ray intersect()'s hit, bit for bit") {
    // rt_global_illumination's waves trace their closest hits in packets and promise the bits of
    // one ray at a time: every field of each lane's hit, partial packets and ray starts past 0
    // included, on the packet widths the CPU has.
    const Scene scene = clutteredScene();
    const RayScene rs(scene, {5, 7, -3});
    Rng rng(4, 5, 6, 13);
    std::vector<Ray> rays(20000);
    for (Ray& r : rays) {
        r.org = {rng.nextFloat() * 240.0f - 120.0f, rng.nextFloat() * 80.0f,
                 rng.nextFloat() * 240.0f - 120.0f};
        r.dir = randomDirection(rng);
        r.tnear = rng.nextFloat() < 0.5f ? 0.0f : rng.nextFloat() * 20.0f;
        r.tfar = rng.nextFloat() * 300.0f;
    }
    for (const int width : {8, 16}) {
        if (width > rs.packetWidth()) continue;  // 16 only where the CPU traces it natively
        CAPTURE(width);
        int hits = 0, differs = 0;
        RayHit packet[kMaxPacketSize];
        for (std::size_t first = 0; first < rays.size();) {
            const int n = 1 + int(first % std::size_t(width));  // 1 … width lanes
            const int count = int(std::min(std::size_t(n), rays.size() - first));
            rs.intersectPacket(rays.data() + first, count, width, packet);
            for (int i = 0; i < count; ++i) {
                const Ray& r = rays[first + std::size_t(i)];
                const RayHit one = rs.intersect(r.org, r.dir, r.tnear, r.tfar);
                const RayHit& p = packet[i];
                hits += one.hit;
                const bool same = p.hit == one.hit &&
                                  (!one.hit || (p.t == one.t && p.mesh == one.mesh &&
                                                p.triangle == one.triangle && p.u == one.u &&
                                                p.v == one.v &&
                                                p.geometricNormal.x == one.geometricNormal.x &&
                                                p.geometricNormal.y == one.geometricNormal.y &&
                                                p.geometricNormal.z == one.geometricNormal.z));
                differs += !same;
            }
            first += std::size_t(count);
        }
        CHECK(hits > 2000);  // the floor, the sphere and the soup are hit, not only missed
        CHECK(differs == 0);
    }
}

TEST_CASE("rays from inside a closed mesh through its vertices and edges never slip out") {
    // The watertight test decides a ray through a shared edge or vertex for one of the triangles
    // around it: a sphere's centre sees the sphere in every direction, edges included.
    Scene scene;
    scene.materials.push_back(test::lambert(0.5f));
    scene.meshes.push_back(test::sphere({3, 4, 5}, 10.0, 64));
    const RayScene rs(scene, {});
    const BvhView bvh = rs.bvh();
    const Mesh& m = scene.meshes[0];
    const Vec3f centre{3, 4, 5};
    int rays = 0, escaped = 0;
    for (std::size_t t = 0; 3 * t < m.indices.size(); ++t) {
        const Vec3f a(m.positions[m.indices[3 * t]]), b(m.positions[m.indices[3 * t + 1]]);
        for (const Vec3f& target : {a, (a + b) * 0.5f}) {
            const Vec3f dir = normalize(target - centre);
            ++rays;
            escaped += traceBvh(bvh, centre, dir, 0.0f, 100.0f, {true, false, 0}) < 0.0f;
        }
    }
    CHECK(rays > 8000);
    CHECK(escaped == 0);
}

TEST_CASE("an empty scene and an empty interval hit nothing") {
    Scene scene;
    const RayScene empty(scene, {});
    CHECK(empty.bvh().nodeCount == 0);
    CHECK(traceBvh(empty.bvh(), {0, 0, 0}, {0, 0, 1}, 0.0f, 10.0f, {}) == -1.0f);
    scene.materials.push_back(test::lambert(0.5f));
    scene.meshes.push_back(test::quad({0, 0, 5}, {1, 0, 0}, {0, 1, 0}, 1.0));
    const RayScene one(scene, {});
    CHECK(traceBvh(one.bvh(), {0, 0, 0}, {0, 0, 1}, 0.0f, 10.0f, {}) == doctest::Approx(5.0f));
    CHECK(traceBvh(one.bvh(), {0, 0, 0}, {0, 0, 1}, 0.0f, 4.0f, {}) == -1.0f);
    CHECK(traceBvh(one.bvh(), {0, 0, 0}, {0, 0, 1}, 6.0f, 5.0f, {}) == -1.0f);
    CHECK(traceBvh(one.bvh(), {0, 0, 0}, {0, 0, 1}, 0.0f, 10.0f, {false, true, 2}) == -1.0f);
}

}  // TEST_SUITE
