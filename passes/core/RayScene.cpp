#include "passes/core/RayScene.h"

#include "passes/core/Error.h"

#include <embree3/rtcore.h>

#include <limits>
#include <string>

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
    mDevice = device;
    mRtcScene = rtc;
    if (!tEmbreeError.empty()) throw Error(tEmbreeError);
}

RayScene::~RayScene() {
    if (mRtcScene) rtcReleaseScene(static_cast<RTCScene>(mRtcScene));
    if (mDevice) rtcReleaseDevice(static_cast<RTCDevice>(mDevice));
}

RayHit RayScene::intersect(const Vec3f& org, const Vec3f& dir, float tnear, float tfar) const {
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

Vec3f RayScene::shadingNormal(const RayHit& hit) const {
    const Mesh& m = mScene.meshes[hit.mesh];
    if (m.normals.empty()) return hit.geometricNormal;
    const uint32_t* tri = &m.indices[3 * hit.triangle];
    const float w = 1.0f - hit.u - hit.v;
    Vec3f n = m.normals[tri[0]] * w + m.normals[tri[1]] * hit.u + m.normals[tri[2]] * hit.v;
    n = normalize(n);
    return length(n) > 0.5f ? n : hit.geometricNormal;
}

const Material& RayScene::material(const RayHit& hit) const {
    return mScene.materials[mScene.meshes[hit.mesh].material];
}

}  // namespace fp
