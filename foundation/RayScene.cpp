#include "foundation/RayScene.h"

#include "foundation/Cuda.h"
#include "foundation/Error.h"

#include <embree3/rtcore.h>
#include <embree3/rtcore_builder.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace fp {

namespace {
void embreeError(void* userPtr, RTCError code, const char* message) {
    // Called on Embree's thread; recorded and raised after the call that failed returns.
    *static_cast<std::string*>(userPtr) = fmt::format("Embree error {}: {}", int(code),
                                                      message ? message : "");
}
thread_local std::string tEmbreeError;
}  // namespace

RayScene::RayScene(const Scene& scene, const Vec3d& origin) : mScene(scene), mOrigin(origin) {
    RTCDevice device = rtcNewDevice(nullptr);
    FP_CHECK(device, "could not create an Embree device (error {})", int(rtcGetDeviceError(nullptr)));
    tEmbreeError.clear();
    rtcSetDeviceErrorFunction(device, embreeError, &tEmbreeError);
    RTCScene rtc = rtcNewScene(device);
    rtcSetSceneBuildQuality(rtc, RTC_BUILD_QUALITY_HIGH);
    // ROBUST keeps rays that graze shared edges from slipping through (hard-case scenes).
    rtcSetSceneFlags(rtc, RTC_SCENE_FLAG_ROBUST);
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* verts = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
            mesh.positions.size()));
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            const Vec3d p = mesh.positions[i] - origin;  // in double, then rounded once
            verts[3 * i + 0] = float(p.x);
            verts[3 * i + 1] = float(p.y);
            verts[3 * i + 2] = float(p.z);
        }
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
            mesh.indices.size() / 3));
        for (std::size_t i = 0; i < mesh.indices.size(); ++i) idx[i] = mesh.indices[i];
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(rtc, geom, unsigned(m));
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(rtc);
    mPacketWidth = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) ? 16 : 8;
    RTCBounds bounds;
    rtcGetSceneBounds(rtc, &bounds);
    mBoundsLo = {bounds.lower_x, bounds.lower_y, bounds.lower_z};
    mBoundsHi = {bounds.upper_x, bounds.upper_y, bounds.upper_z};
    mDevice = device;
    mRtcScene = rtc;
    if (!tEmbreeError.empty()) throw Error(tEmbreeError);
}

struct RayScene::OwnBvh {
    std::vector<BvhNode> nodes;
    std::vector<BvhTriangle> triangles;
    std::vector<BvhShading> shading;
    std::vector<BvhMaterial> materials;
    // null until deviceBvh()
    std::shared_ptr<void> deviceNodes, deviceTriangles, deviceShading, deviceMaterials;
};

RayScene::~RayScene() {
    if (mRtcScene) rtcReleaseScene(static_cast<RTCScene>(mRtcScene));
    if (mDevice) rtcReleaseDevice(static_cast<RTCDevice>(mDevice));
}

RayHit RayScene::intersect(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) const {
    if (mLog) {
        std::lock_guard<std::mutex> lock(mLogMutex);
        if (mLog) mLog->closestRays.push_back({org, dir, tnear, tfar});
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = org.x;
    rh.ray.org_y = org.y;
    rh.ray.org_z = org.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = tnear;
    rh.ray.tfar = tfar;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(static_cast<RTCScene>(mRtcScene), &context, &rh);
    RayHit h;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
    h.hit = true;
    h.t = rh.ray.tfar;
    h.mesh = rh.hit.geomID;
    h.triangle = rh.hit.primID;
    h.u = rh.hit.u;
    h.v = rh.hit.v;
    h.geometricNormal = normalize(Vec3f{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z});
    return h;
}

bool RayScene::occluded(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) const {
    if (mLog) {
        FP_ASSERT(tnear == 0.0f);  // the log's rays start at their origin, as RayArrays' do
        const RayArrays r{&org.x, &org.y, &org.z, &dir.x, &dir.y, &dir.z, &tfar};
        log(r, 1, false);
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    ray.org_x = org.x;
    ray.org_y = org.y;
    ray.org_z = org.z;
    ray.dir_x = dir.x;
    ray.dir_y = dir.y;
    ray.dir_z = dir.z;
    ray.tnear = tnear;
    ray.tfar = tfar;
    ray.mask = 0xFFFFFFFFu;
    rtcOccluded1(static_cast<RTCScene>(mRtcScene), &context, &ray);
    // Embree marks an occluded ray by setting tfar to −∞.
    return ray.tfar == -std::numeric_limits<float>::infinity();
}

namespace {
// Embree's packets (RTCRay8, RTCRay16) need their width's alignment; a lane is valid when its mask
// is −1. Lanes past `count` repeat ray 0, so every lane Embree might look at holds a finite ray.
template <int W, class Packet>
void fillPacket(Packet& r, int* valid, const RayArrays& rays, int count, const bool* use) {
    for (int i = 0; i < W; ++i) {
        const bool on = i < count && (!use || use[i]);
        valid[i] = on ? -1 : 0;
        const int k = i < count ? i : 0;
        r.org_x[i] = rays.orgX[k];
        r.org_y[i] = rays.orgY[k];
        r.org_z[i] = rays.orgZ[k];
        r.dir_x[i] = rays.dirX[k];
        r.dir_y[i] = rays.dirY[k];
        r.dir_z[i] = rays.dirZ[k];
        r.tnear[i] = 0.0f;
        r.tfar[i] = rays.tfar[k];
        r.mask[i] = 0xFFFFFFFFu;
        r.time[i] = 0.0f;
        r.flags[i] = 0;
        r.id[i] = unsigned(i);
    }
}

template <int W> struct Packet;
template <> struct Packet<8> {
    using Ray = RTCRay8;
    using RayHit = RTCRayHit8;
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
        rtcOccluded8(v, s, c, r);
    }
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
        rtcIntersect8(v, s, c, r);
    }
};
template <> struct Packet<16> {
    using Ray = RTCRay16;
    using RayHit = RTCRayHit16;
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
        rtcOccluded16(v, s, c, r);
    }
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
        rtcIntersect16(v, s, c, r);
    }
};

// Occlusion of rays [0, count) in one packet of width W, and with `t` the closest hit of the
// blocked ones: any-hit first (most shadow rays of a lit frame are unblocked, and the occlusion
// query stops at the first occluder), then the nearest occluder on the blocked lanes only.
template <int W>
void tracePacket(RTCScene scene, const RayArrays& rays, int count, bool* occluded, float* t) {
    alignas(4 * W) int valid[W];
    alignas(4 * W) typename Packet<W>::Ray r;
    fillPacket<W>(r, valid, rays, count, nullptr);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    Packet<W>::occluded(valid, scene, &context, &r);
    bool anyBlocked = false;
    for (int i = 0; i < count; ++i) {
        occluded[i] = r.tfar[i] == -std::numeric_limits<float>::infinity();
        anyBlocked |= occluded[i];
    }
    if (!t)
        return;
    std::fill(t, t + count, -1.0f);
    if (!anyBlocked)
        return;
    alignas(4 * W) typename Packet<W>::RayHit rh;
    fillPacket<W>(rh.ray, valid, rays, count, occluded);
    for (int i = 0; i < W; ++i) rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    Packet<W>::intersect(valid, scene, &context, &rh);
    for (int i = 0; i < count; ++i)
        if (occluded[i] && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID)
            t[i] = rh.ray.tfar[i];
}
// The closest hits of rays [0, count) in one packet of width W, each as RayScene::intersect
// reads its ray's hit.
template <int W>
void intersectRays(RTCScene scene, const Ray* rays, int count, RayHit* hits) {
    alignas(4 * W) int valid[W];
    alignas(4 * W) typename Packet<W>::RayHit rh;
    for (int i = 0; i < W; ++i) {
        const Ray& q = rays[i < count ? i : 0];  // lanes past `count` repeat ray 0, switched off
        valid[i] = i < count ? -1 : 0;
        rh.ray.org_x[i] = q.org.x;
        rh.ray.org_y[i] = q.org.y;
        rh.ray.org_z[i] = q.org.z;
        rh.ray.dir_x[i] = q.dir.x;
        rh.ray.dir_y[i] = q.dir.y;
        rh.ray.dir_z[i] = q.dir.z;
        rh.ray.tnear[i] = q.tnear;
        rh.ray.tfar[i] = q.tfar;
        rh.ray.mask[i] = 0xFFFFFFFFu;
        rh.ray.time[i] = 0.0f;
        rh.ray.flags[i] = 0;
        rh.ray.id[i] = unsigned(i);
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    Packet<W>::intersect(valid, scene, &context, &rh);
    for (int i = 0; i < count; ++i) {
        RayHit& h = hits[i];
        h = RayHit{};
        if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
        h.hit = true;
        h.t = rh.ray.tfar[i];
        h.mesh = rh.hit.geomID[i];
        h.triangle = rh.hit.primID[i];
        h.u = rh.hit.u[i];
        h.v = rh.hit.v[i];
        h.geometricNormal = normalize(Vec3f{rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]});
    }
}
}  // namespace

void RayScene::intersectPacket(const Ray* rays, int count, int width, RayHit* hits) const {
    FP_ASSERT((width == 8 || width == 16) && count >= 1 && count <= width);
    if (mLog) {
        std::lock_guard<std::mutex> lock(mLogMutex);
        if (mLog) mLog->closestRays.insert(mLog->closestRays.end(), rays, rays + count);
    }
    const auto scene = static_cast<RTCScene>(mRtcScene);
    if (width == 16)
        intersectRays<16>(scene, rays, count, hits);
    else
        intersectRays<8>(scene, rays, count, hits);
}

void RayScene::occludedPacket(const RayArrays& rays, int count, int width, bool* occluded) const {
    occludedWithDistancePacket(rays, count, width, occluded, nullptr);
}

void RayScene::occludedWithDistancePacket(const RayArrays& rays, int count, int width,
                                          bool* occluded, float* t) const {
    FP_ASSERT((width == 8 || width == 16) && count >= 1 && count <= width);
    if (mLog) log(rays, count, t != nullptr);
    const auto scene = static_cast<RTCScene>(mRtcScene);
    if (width == 16)
        tracePacket<16>(scene, rays, count, occluded, t);
    else
        tracePacket<8>(scene, rays, count, occluded, t);
}

RayHit RayScene::intersectInstance(const Vec3f& org, const Vec3f& dir, float tnear, float tfar,
                                   uint32_t instanceId) const {
    // Step past other objects' surfaces; a bounded number of layers keeps a pathological scene
    // (thousands of coplanar sheets) from stalling a pixel.
    for (int layer = 0; layer < 64 && tnear <= tfar; ++layer) {
        const RayHit h = intersect(org, dir, tnear, tfar);
        if (!h.hit || mScene.meshes[h.mesh].instanceId == instanceId) return h;
        tnear = std::nextafter(h.t, std::numeric_limits<float>::infinity());
    }
    return {};
}

float RayScene::farthestDistance(const Vec3f& p) const {
    return fp::farthestDistance(mBoundsLo, mBoundsHi, p);
}

namespace {
// rtcBuildBVH's tree, in memory from its thread-local allocator, before it is flattened into
// BvhNodes: inner nodes with two children and their boxes, leaves with their triangles.
struct BuildNode {
    bool leaf;
};
struct BuildInner : BuildNode {
    BuildNode* children[2];
    RTCBounds bounds[2];
    unsigned childCount;
};
struct BuildLeaf : BuildNode {
    unsigned count;
    unsigned mesh[RTC_BUILD_MAX_PRIMITIVES_PER_LEAF], triangle[RTC_BUILD_MAX_PRIMITIVES_PER_LEAF];
};

void* createInner(RTCThreadLocalAllocator alloc, unsigned childCount, void*) {
    auto* n = static_cast<BuildInner*>(rtcThreadLocalAlloc(alloc, sizeof(BuildInner), 16));
    n->leaf = false;
    n->childCount = childCount;
    n->children[0] = n->children[1] = nullptr;
    return n;
}
void setChildren(void* node, void** children, unsigned count, void*) {
    auto* n = static_cast<BuildInner*>(node);
    for (unsigned i = 0; i < count && i < 2; ++i) n->children[i] = static_cast<BuildNode*>(children[i]);
}
void setBounds(void* node, const RTCBounds** bounds, unsigned count, void*) {
    auto* n = static_cast<BuildInner*>(node);
    for (unsigned i = 0; i < count && i < 2; ++i) n->bounds[i] = *bounds[i];
}
void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*) {
    auto* n = static_cast<BuildLeaf*>(rtcThreadLocalAlloc(alloc, sizeof(BuildLeaf), 16));
    n->leaf = true;
    n->count = unsigned(count);
    for (size_t i = 0; i < count; ++i) {
        n->mesh[i] = prims[i].geomID;
        n->triangle[i] = prims[i].primID;
    }
    return n;
}

constexpr unsigned kBvhLeafSize = 4;

// Depth-first, each inner node before its children, so node 0 is the root.
class BvhFlattener {
public:
    BvhFlattener(const Scene& scene, const std::vector<std::array<Vec3f, 3>>& corners,
                 const std::vector<std::size_t>& firstTriangle, std::vector<BvhNode>& nodes,
                 std::vector<BvhTriangle>& triangles, std::vector<BvhShading>& shading)
        : mScene(scene),
          mCorners(corners),
          mFirst(firstTriangle),
          mNodes(nodes),
          mTriangles(triangles),
          mShading(shading) {}

    int inner(const BuildInner& b) {
        const int index = int(mNodes.size());
        mNodes.push_back({});
        for (int c = 0; c < 2; ++c) {
            if (c >= int(b.childCount) || !b.children[c]) {
                mNodes[index].count[c] = -1;
                continue;
            }
            const RTCBounds& r = b.bounds[c];
            mNodes[index].lo[c] = {r.lower_x, r.lower_y, r.lower_z};
            mNodes[index].hi[c] = {r.upper_x, r.upper_y, r.upper_z};
            const auto [child, count] = place(*b.children[c]);
            mNodes[index].child[c] = child;  // mNodes may have grown: index again
            mNodes[index].count[c] = count;
        }
        return index;
    }

    /// The root, always an inner node (a lone leaf gets a parent with one child).
    void root(const BuildNode& n, const Vec3f& lo, const Vec3f& hi) {
        if (!n.leaf) {
            inner(static_cast<const BuildInner&>(n));
            return;
        }
        mNodes.push_back({});
        mNodes[0].lo[0] = lo;
        mNodes[0].hi[0] = hi;
        mNodes[0].count[1] = -1;
        const auto [child, count] = place(n);
        mNodes[0].child[0] = child;
        mNodes[0].count[0] = count;
    }

private:
    std::pair<int32_t, int32_t> place(const BuildNode& n) {
        if (!n.leaf) return {inner(static_cast<const BuildInner&>(n)), 0};
        const auto& leaf = static_cast<const BuildLeaf&>(n);
        const int32_t first = int32_t(mTriangles.size());
        for (unsigned i = 0; i < leaf.count; ++i) {
            const auto& v = mCorners[mFirst[leaf.mesh[i]] + leaf.triangle[i]];
            BvhTriangle tri{};
            tri.v0 = v[0];
            tri.v1 = v[1];
            tri.v2 = v[2];
            const Mesh& mesh = mScene.meshes[leaf.mesh[i]];
            tri.instanceId = mesh.instanceId;
            mTriangles.push_back(tri);
            BvhShading shading{};
            shading.material = uint32_t(mesh.material);
            shading.lightShape = mesh.shapeOf >= 0 ? 1u : 0u;
            if (!mesh.normals.empty()) {
                const uint32_t* corner = &mesh.indices[3 * std::size_t(leaf.triangle[i])];
                shading.smooth = 1;
                shading.n0 = mesh.normals[corner[0]];
                shading.n1 = mesh.normals[corner[1]];
                shading.n2 = mesh.normals[corner[2]];
            }
            mShading.push_back(shading);
        }
        return {first, int32_t(leaf.count)};
    }

    const Scene& mScene;
    const std::vector<std::array<Vec3f, 3>>& mCorners;
    const std::vector<std::size_t>& mFirst;
    std::vector<BvhNode>& mNodes;
    std::vector<BvhTriangle>& mTriangles;
    std::vector<BvhShading>& mShading;
};
}  // namespace

BvhView RayScene::bvh() const {
    std::lock_guard<std::mutex> lock(mBvhMutex);
    if (!mBvh) {
        auto own = std::make_unique<OwnBvh>();
        // Each triangle's corners as Embree holds them: offsets from the origin, in double, then
        // rounded once. The build sorts the boxes; the flattening copies the corners in order.
        std::vector<std::array<Vec3f, 3>> corners;
        std::vector<std::size_t> firstTriangle;
        std::vector<RTCBuildPrimitive> prims;
        for (std::size_t m = 0; m < mScene.meshes.size(); ++m) {
            const Mesh& mesh = mScene.meshes[m];
            firstTriangle.push_back(corners.size());
            for (std::size_t t = 0; 3 * t + 2 < mesh.indices.size(); ++t) {
                std::array<Vec3f, 3> v;
                for (int k = 0; k < 3; ++k)
                    v[k] = Vec3f(mesh.positions[mesh.indices[3 * t + k]] - mOrigin);
                corners.push_back(v);
                RTCBuildPrimitive p;
                p.lower_x = std::min({v[0].x, v[1].x, v[2].x});
                p.lower_y = std::min({v[0].y, v[1].y, v[2].y});
                p.lower_z = std::min({v[0].z, v[1].z, v[2].z});
                p.upper_x = std::max({v[0].x, v[1].x, v[2].x});
                p.upper_y = std::max({v[0].y, v[1].y, v[2].y});
                p.upper_z = std::max({v[0].z, v[1].z, v[2].z});
                p.geomID = unsigned(m);
                p.primID = unsigned(t);
                prims.push_back(p);
            }
        }
        if (!prims.empty()) {
            RTCBVH tree = rtcNewBVH(static_cast<RTCDevice>(mDevice));
            RTCBuildArguments args = rtcDefaultBuildArguments();
            args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;  // binned SAH (HIGH's spatial splits
                                                           // would need a split callback)
            args.maxBranchingFactor = 2;
            args.maxDepth = kBvhMaxDepth - 2;
            args.maxLeafSize = kBvhLeafSize;
            args.bvh = tree;
            args.primitives = prims.data();
            args.primitiveCount = prims.size();
            args.primitiveArrayCapacity = prims.size();
            args.createNode = createInner;
            args.setNodeChildren = setChildren;
            args.setNodeBounds = setBounds;
            args.createLeaf = createLeaf;
            tEmbreeError.clear();
            const auto* root = static_cast<const BuildNode*>(rtcBuildBVH(&args));
            if (!root || !tEmbreeError.empty()) {
                rtcReleaseBVH(tree);
                throw Error(fmt::format("building the scene's BVH failed: {}",
                                        tEmbreeError.empty() ? "no tree" : tEmbreeError));
            }
            own->triangles.reserve(prims.size());
            own->shading.reserve(prims.size());
            BvhFlattener(mScene, corners, firstTriangle, own->nodes, own->triangles, own->shading)
                .root(*root, mBoundsLo, mBoundsHi);
            rtcReleaseBVH(tree);
        }
        for (const Material& m : mScene.materials)
            own->materials.push_back({m.baseColor, m.metallic, m.specular, m.roughness, m.emission});
        mBvh = std::move(own);
    }
    return {mBvh->nodes.data(), mBvh->triangles.data(), int(mBvh->nodes.size()), mBoundsLo,
            mBoundsHi,          mBvh->shading.data(),   mBvh->materials.data()};
}

BvhView RayScene::deviceBvh() const {
    BvhView view = bvh();
    std::lock_guard<std::mutex> lock(mBvhMutex);
    if (view.nodeCount > 0 && !mBvh->deviceNodes) {
        mBvh->deviceNodes = cuda::uploadBytes(view.nodes, sizeof(BvhNode) * mBvh->nodes.size());
        mBvh->deviceTriangles =
            cuda::uploadBytes(view.triangles, sizeof(BvhTriangle) * mBvh->triangles.size());
        mBvh->deviceShading =
            cuda::uploadBytes(view.shading, sizeof(BvhShading) * mBvh->shading.size());
        mBvh->deviceMaterials =
            cuda::uploadBytes(view.materials, sizeof(BvhMaterial) * mBvh->materials.size());
    }
    if (view.nodeCount > 0) {
        view.nodes = static_cast<const BvhNode*>(mBvh->deviceNodes.get());
        view.triangles = static_cast<const BvhTriangle*>(mBvh->deviceTriangles.get());
        view.shading = static_cast<const BvhShading*>(mBvh->deviceShading.get());
        view.materials = static_cast<const BvhMaterial*>(mBvh->deviceMaterials.get());
    }
    return view;
}

void RayScene::setRayLog(RayLog* log) const {
    std::lock_guard<std::mutex> lock(mLogMutex);
    mLog = log;
}

void RayScene::log(const RayArrays& rays, int count, bool closestHits) const {
    std::lock_guard<std::mutex> lock(mLogMutex);
    if (!mLog) return;
    for (int i = 0; i < count; ++i) mLog->rays.push_back(rays.at(i));
    mLog->closestHits |= closestHits;
}

Vec3f RayScene::shadingNormal(const RayHit& hit) const {
    const Mesh& m = mScene.meshes[hit.mesh];
    if (m.normals.empty()) return hit.geometricNormal;
    const uint32_t* tri = &m.indices[3 * hit.triangle];
    return interpolatedNormal(m.normals[tri[0]], m.normals[tri[1]], m.normals[tri[2]], hit.u, hit.v,
                              hit.geometricNormal);
}

const Material& RayScene::material(const RayHit& hit) const {
    return mScene.materials[mScene.meshes[hit.mesh].material];
}

}  // namespace fp
