// ShadowLanes.h: compiled once per x86 instruction set (foreach_target.h re-includes this file);
// lanes(), setupRow and sampleRow call the widest one the CPU has.
//
// Each lane repeats, operation for operation, what RTShadowsPass.cpp's scalar reference does with
// Camera.h's translatedFromPixel, ShadowRayGenerator.h (lightReaches, lightCentreDirection,
// sampleLight) and Rng (Random.h): the same products and sums in the same order, double precision where the scalar
// code rebuilds positions in double, std::min/max/clamp's NaN rules (LaneMath.h).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/rt_shadows/ShadowLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "screenspace/LaneMath.h"
#include "foundation/Random.h"
#include "foundation/ShadingModel.h"
#include "passes/rt_shadows/ShadowLanes.h"

#include <algorithm>
#include <cmath>

HWY_BEFORE_NAMESPACE();
namespace fp::shadow::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using fp::HWY_NAMESPACE::clampLike;
using fp::HWY_NAMESPACE::maxLike;
using fp::HWY_NAMESPACE::concentricDiskLanes;
using fp::HWY_NAMESPACE::sinCosLanes;

using D = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<D>;
using DU = hn::RebindToUnsigned<D>;
using V = hn::Vec<D>;
using VI = hn::Vec<DI>;
using VU = hn::Vec<DU>;
using M = hn::Mask<D>;
using DD = hn::ScalableTag<double>;
using DF = hn::Rebind<float, DD>;  // the floats of one double vector
using VD = hn::Vec<DD>;
static_assert(HWY_MAX_BYTES / sizeof(float) <= kMaxLanes, "a row holds whole vectors");

using V3 = fp::HWY_NAMESPACE::Vec3Lanes<V>;
using fp::HWY_NAMESPACE::dot3;
using fp::HWY_NAMESPACE::normalize3;

// Lanes [i, i + N) of three planes.
HWY_INLINE V3 load3(const float* x, const float* y, const float* z, int i) {
    return fp::HWY_NAMESPACE::load3(D(), x + i, y + i, z + i);
}

HWY_INLINE V3 splat(const Vec3f& v) {
    const D d;
    return {hn::Set(d, v.x), hn::Set(d, v.y), hn::Set(d, v.z)};
}

HWY_INLINE V3 sub3(const V3& a, const V3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}

HWY_INLINE V length3(const V3& a) {
    return hn::Sqrt(dot3(a, a));
}

// a / s, component by component (Vec3f's operator/).
HWY_INLINE V3 div3(const V3& a, V s) {
    return {a.x / s, a.y / s, a.z / s};
}

// PCG's state step and output permutation in every lane: pcgHash (Random.h) is one step and
// the permutation, Rng::nextUint steps its state and permutes it.
HWY_INLINE VU pcgStep(VU v) {
    const DU du;
    return v * hn::Set(du, 747796405u) + hn::Set(du, 2891336453u);
}

HWY_INLINE VU pcgPermute(VU state) {
    const DU du;
    const VU word = hn::Xor(state >> (hn::ShiftRight<28>(state) + hn::Set(du, 4u)), state) *
                    hn::Set(du, 277803737u);
    return hn::Xor(hn::ShiftRight<22>(word), word);
}

HWY_INLINE VU pcgHash(VU v) {
    return pcgPermute(pcgStep(v));
}

// Rng::nextFloat in every lane: advances `state` and returns the top 24 bits over 2²⁴.
HWY_INLINE V nextFloat(VU& state) {
    const D d;
    state = pcgStep(state);
    // Below 2²⁴: the conversion from int is exact, as float(uint32) is in the scalar code.
    return hn::ConvertTo(d, hn::BitCast(DI(), hn::ShiftRight<8>(pcgPermute(state)))) *
           hn::Set(d, 1.0f / 16777216.0f);
}

// truncToInt(double(v), 0, hi) (FloatToInt.h) for a float v: NaN and negatives give 0.
HWY_INLINE VI truncClamped(V v, float hi) {
    const D d;
    V c = hn::IfThenElse(v >= hn::Set(d, hi), hn::Set(d, hi), v);
    c = hn::IfThenElse(v >= hn::Zero(d), c, hn::Zero(d));
    return hn::ConvertTo(DI(), c);
}

// lightCentreDirection (ShadowRayGenerator.h).
HWY_INLINE V3 centreDirection(const ShadowLightShape& l, const V3& p) {
    if (l.type == LightType::Directional)
        return splat(l.toLight);
    return normalize3(sub3(splat(l.position), p));
}

// lightReaches (ShadowRayGenerator.h; all lanes true for a directional light).
HWY_INLINE M reaches(const ShadowLightShape& l, const V3& p) {
    const D d;
    if (l.type == LightType::Directional)
        return hn::FirstN(d, hn::Lanes(d));
    const V3 toLight = sub3(splat(l.position), p);
    const M inRange = hn::Not(length3(toLight) > hn::Set(d, l.reachBound));
    const V3 away = {hn::Neg(toLight.x), hn::Neg(toLight.y), hn::Neg(toLight.z)};
    if (l.type == LightType::Spot)
        return hn::And(inRange, dot3(normalize3(away), splat(l.axis)) > hn::Set(d, l.cosOuter));
    if (l.type == LightType::Rect)
        return hn::And(inRange, dot3(away, splat(l.axis)) > hn::Zero(d));
    return inRange;
}

HWY_INLINE M isModel(VI model, int which) {
    return hn::RebindMask(D(), model == hn::Set(DI(), which));
}

int lanesHere() {
    return int(hn::Lanes(D()));
}

void setupRowHere(const RowContext& c, const RowInputs& in, RowPixels& out) {
    const D d;
    const DI di;
    const DU du;
    const DD dd;
    const DF df;
    const int N = int(hn::Lanes(d)), ND = int(hn::Lanes(dd));
    const int n = in.count;
    const int padded = (n + N - 1) / N * N;  // whole float vectors (a multiple of ND)
    out.x0 = in.x0;
    out.count = n;

    // Whole vectors are read from the planes where they lie inside the row; a last, partial
    // vector from a zero-padded copy of the row's tail.
    enum Input { kDepth, kNormalX, kNormalY, kNormalZ, kModel, kInputCount };
    const int whole = n / N * N;
    HWY_ALIGN float tail[kInputCount][kMaxLanes] = {};
    const float* planes[kInputCount] = {in.depth, in.normalX, in.normalY, in.normalZ, in.model};
    for (int p = 0; p < kInputCount; ++p)
        std::copy(planes[p] + whole, planes[p] + n, tail[p]);
    // Plane p's floats from pixel i on (i < padded; a vector from i stays in one part).
    auto row = [&](int p, int i) { return i < whole ? planes[p] + i : tail[p] + (i - whole); };

    // Camera.h translatedFromPixel in double, then the float position, eye distance and
    // direction to the eye: Vec3f(eyeOffset + offset), float(length), Vec3f(−offset / length).
    const CameraView& cam = c.camera;
    const VD rowTerm = hn::Set(dd, cam.screenY(double(in.y)) - cam.cy);
    const VD laneD = hn::Iota(dd, 0.0);
    for (int i = 0; i < padded; i += ND) {
        const VD z = hn::PromoteTo(dd, hn::LoadU(df, row(kDepth, i)));
        const VD pixelX = laneD + hn::Set(dd, double(in.x0 + i));  // exact: small integers
        const VD screenX = (pixelX + hn::Set(dd, 0.5)) / hn::Set(dd, double(cam.width)) *
                               hn::Set(dd, 2.0) -
                           hn::Set(dd, 1.0);
        const VD vx = (screenX - hn::Set(dd, cam.cx)) * z / hn::Set(dd, cam.fx);
        const VD vy = rowTerm * z / hn::Set(dd, cam.fy);
        const VD ox = hn::Set(dd, cam.right.x) * vx + hn::Set(dd, cam.up.x) * vy +
                      hn::Set(dd, cam.forward.x) * z;
        const VD oy = hn::Set(dd, cam.right.y) * vx + hn::Set(dd, cam.up.y) * vy +
                      hn::Set(dd, cam.forward.y) * z;
        const VD oz = hn::Set(dd, cam.right.z) * vx + hn::Set(dd, cam.up.z) * vy +
                      hn::Set(dd, cam.forward.z) * z;
        hn::StoreU(hn::DemoteTo(df, hn::Set(dd, c.eyeOffset.x) + ox), df, out.px + i);
        hn::StoreU(hn::DemoteTo(df, hn::Set(dd, c.eyeOffset.y) + oy), df, out.py + i);
        hn::StoreU(hn::DemoteTo(df, hn::Set(dd, c.eyeOffset.z) + oz), df, out.pz + i);
        const VD distance = hn::Sqrt(ox * ox + oy * oy + oz * oz);
        hn::StoreU(hn::DemoteTo(df, distance), df, out.eyeDistance + i);
        hn::StoreU(hn::DemoteTo(df, hn::Neg(ox) / distance), df, out.ex + i);
        hn::StoreU(hn::DemoteTo(df, hn::Neg(oy) / distance), df, out.ey + i);
        hn::StoreU(hn::DemoteTo(df, hn::Neg(oz) / distance), df, out.ez + i);
    }

    // Lit surfaces the light reaches, their normals (hair: towards the light) and random stream.
    const uint32_t rowKey = fp::pcgHash(uint32_t(in.y) ^ c.rngKey);
    const VI lane = hn::Iota(di, 0);
    for (int i = 0; i < padded; i += N) {
        const V z = hn::LoadU(d, row(kDepth, i));
        const VI modelId = truncClamped(hn::LoadU(d, row(kModel, i)), 255.0f);
        const M lit = hn::And(hn::And(z > hn::Zero(d), hn::Not(hn::IsInf(z))),
                              hn::Not(isModel(modelId, kUnlit)));
        const V3 p = load3(out.px, out.py, out.pz, i);
        const M active = hn::And(hn::And(hn::FirstN(d, size_t(n - i)), lit), reaches(c.light, p));
        hn::StoreU(hn::VecFromMask(di, hn::RebindMask(di, active)), di, out.active + i);
        hn::StoreU(modelId, di, out.model + i);
        V3 normal =
            fp::HWY_NAMESPACE::load3(d, row(kNormalX, i), row(kNormalY, i), row(kNormalZ, i));
        const M hair = isModel(modelId, kHair);
        if (!hn::AllFalse(d, hair)) {
            const V3 towardsLight = centreDirection(c.light, p);
            normal = {hn::IfThenElse(hair, towardsLight.x, normal.x),
                      hn::IfThenElse(hair, towardsLight.y, normal.y),
                      hn::IfThenElse(hair, towardsLight.z, normal.z)};
        }
        hn::StoreU(normal.x, d, out.nx + i);
        hn::StoreU(normal.y, d, out.ny + i);
        hn::StoreU(normal.z, d, out.nz + i);
        const VU x = hn::BitCast(du, lane + hn::Set(di, in.x0 + i));
        hn::StoreU(pcgHash(hn::Xor(x, hn::Set(du, rowKey))), du, out.rng + i);
    }
}

// sampleLight (ShadowRayGenerator.h) from origins `o` with the random pair (u, v).
HWY_INLINE void lightSample(const ShadowLightShape& l, const V3& o, V u, V v, V3& dir, V& tfar) {
    const D d;
    const V one = hn::Set(d, 1.0f), two = hn::Set(d, 2.0f), zero = hn::Zero(d);
    switch (l.type) {
    case LightType::Directional: {
        V dx, dy;
        concentricDiskLanes(d, u, v, dx, dy);
        const V radius = hn::Set(d, l.sourceRadius);
        const V3 t = splat(l.toLightT), b = splat(l.toLightB), L = splat(l.toLight);
        dir = normalize3(V3{L.x + (t.x * dx + b.x * dy) * radius, L.y + (t.y * dx + b.y * dy) * radius,
                          L.z + (t.z * dx + b.z * dy) * radius});
        tfar = hn::Set(d, ShadowLightShape::kDirectionalTraceDistance);
        return;
    }
    case LightType::Rect: {
        const V su = two * u - one, sv = two * v - one;
        const V3 q = {hn::Set(d, l.position.x) + hn::Set(d, l.halfU.x) * su +
                          hn::Set(d, l.halfV.x) * sv,
                      hn::Set(d, l.position.y) + hn::Set(d, l.halfU.y) * su +
                          hn::Set(d, l.halfV.y) * sv,
                      hn::Set(d, l.position.z) + hn::Set(d, l.halfU.z) * su +
                          hn::Set(d, l.halfV.z) * sv};
        const V3 toSample = sub3(q, o);
        const V dist = length3(toSample);
        dir = div3(toSample, dist);
        tfar = dist * hn::Set(d, 1.0f - 1e-4f);
        return;
    }
    case LightType::Point:
    case LightType::Spot:
    default: {  // as sampleLight (ShadowRayGenerator.h): neither directional nor rect
        const V3 toCentre = sub3(splat(l.position), o);
        const V dist = length3(toCentre);
        const V3 L = div3(toCentre, dist);
        const V r = hn::Set(d, l.radius);
        const M inside = dist <= r;
        // A point, or a pixel inside the sphere: straight at the centre.
        const V pointTfar = hn::IfThenElse(inside, zero, dist);
        if (l.radius <= 0.0f) {
            dir = L;
            tfar = pointTfar;
            return;
        }
        const V sinMax = r / dist;
        const V cosMax = hn::Sqrt(maxLike(zero, one - sinMax * sinMax));
        const V cosT = one - u * (one - cosMax);
        const V sinT = hn::Sqrt(maxLike(zero, one - cosT * cosT));
        const V phi = hn::Set(d, 2.0f * kPiF) * v;
        V s, c;
        sinCosLanes(d, phi, s, c);
        // orthonormalBasis(L) (Sampling.h).
        const V sign = hn::IfThenElse(L.z >= zero, one, hn::Neg(one));
        const V a = hn::Neg(one) / (sign + L.z);
        const V k = L.x * L.y * a;
        const V3 t = {one + sign * a * L.x * L.x, sign * k, hn::Neg(sign) * L.x};
        const V3 b = {k, sign + a * L.y * L.y, hn::Neg(L.y)};
        const V sc = sinT * c, ss = sinT * s;
        const V3 cone = normalize3(V3{t.x * sc + b.x * ss + L.x * cosT, t.y * sc + b.y * ss + L.y * cosT,
                                    t.z * sc + b.z * ss + L.z * cosT});
        const V along = dist * cosT;
        const V coneTfar =
            maxLike(zero, along - hn::Sqrt(maxLike(zero, r * r - dist * dist * sinT * sinT)));
        dir = {hn::IfThenElse(inside, L.x, cone.x), hn::IfThenElse(inside, L.y, cone.y),
               hn::IfThenElse(inside, L.z, cone.z)};
        tfar = hn::IfThenElse(inside, pointTfar, coneTfar);
        return;
    }
    }
}

void sampleRowHere(const RowContext& c, int stripRow, RowPixels& px, StripRays& rays) {
    const D d;
    const DI di;
    const DU du;
    const int N = int(hn::Lanes(d));
    const ShadowLightShape& l = c.light;
    const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
    const VI owners = hn::Iota(di, ownerOf(stripRow, 0));
    for (int i = 0; i < px.count; i += N) {
        const M live = hn::RebindMask(d, hn::LoadU(di, px.active + i) != hn::Zero(di));
        if (hn::AllFalse(d, live))
            continue;
        // Both numbers are drawn whether or not the pixel's ray is culled (the scalar order);
        // lanes of inactive pixels advance too, but their streams are never read.
        VU state = hn::LoadU(du, px.rng + i);
        const V u = nextFloat(state);
        const V v = nextFloat(state);
        hn::StoreU(state, du, px.rng + i);

        const V3 p = load3(px.px, px.py, px.pz, i);
        const V3 n = load3(px.nx, px.ny, px.nz, i);
        const VI model = hn::LoadU(di, px.model + i);
        const V NoL = dot3(n, centreDirection(l, p));
        // cullsBackFacing: never for rect lights, else all but hair, eye, foliage and subsurface.
        const M thicknessModel = hn::Or(isModel(model, kSubsurface), isModel(model, kHair));
        const M transmissive = hn::Or(thicknessModel, isModel(model, kSubsurfaceProfile));
        const M culled =
            l.type == LightType::Rect
                ? hn::FirstN(d, 0)
                : hn::And(NoL <= zero, hn::Not(hn::Or(hn::Or(transmissive, isModel(model, kEye)),
                                                      isModel(model, kTwoSidedFoliage))));
        const M traces = hn::AndNot(culled, live);
        if (hn::AllFalse(d, traces))
            continue;

        // algorithms §9.2 biases: towards the camera by max(1e-4·distance, bias), then along the
        // normal by lerp(bias, 0.01 cm, N·L), backwards for a transmissive pixel facing away.
        const V3 e = load3(px.ex, px.ey, px.ez, i);
        const V toEye =
            maxLike(hn::Set(d, 1e-4f) * hn::LoadU(d, px.eyeDistance + i), hn::Set(d, c.maxBias));
        const V nb = hn::Set(d, c.maxBias) +
                     hn::Set(d, c.minBias - c.maxBias) * clampLike(NoL, zero, one);
        const M backSide = c.transmission ? hn::And(NoL <= zero, transmissive) : hn::FirstN(d, 0);
        const V along = hn::IfThenElse(backSide, hn::Neg(nb), nb);
        const V3 o = {p.x + e.x * toEye + n.x * along, p.y + e.y * toEye + n.y * along,
                      p.z + e.z * toEye + n.z * along};
        V3 dir;
        V tfar;
        lightSample(l, o, u, v, dir, tfar);

        const int k = rays.count;
        hn::CompressStore(o.x, traces, d, rays.ox + k);
        hn::CompressStore(o.y, traces, d, rays.oy + k);
        hn::CompressStore(o.z, traces, d, rays.oz + k);
        hn::CompressStore(dir.x, traces, d, rays.dx + k);
        hn::CompressStore(dir.y, traces, d, rays.dy + k);
        hn::CompressStore(dir.z, traces, d, rays.dz + k);
        hn::CompressStore(tfar, traces, d, rays.tfar + k);
        rays.count += int(hn::CompressStore(owners + hn::Set(di, i), hn::RebindMask(di, traces),
                                            di, rays.owner + k));
    }
}

}  // namespace fp::shadow::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::shadow {

HWY_EXPORT(lanesHere);
HWY_EXPORT(setupRowHere);
HWY_EXPORT(sampleRowHere);

int lanes() {
    return HWY_DYNAMIC_DISPATCH(lanesHere)();
}

void setupRow(const RowContext& c, const RowInputs& in, RowPixels& out) {
    HWY_DYNAMIC_DISPATCH(setupRowHere)(c, in, out);
}

void sampleRow(const RowContext& c, int stripRow, RowPixels& px, StripRays& rays) {
    HWY_DYNAMIC_DISPATCH(sampleRowHere)(c, stripRow, px, rays);
}

}  // namespace fp::shadow
#endif
