#pragma once
// The screen-space ray march through the furthest HZB (algorithms §4.5–4.6, Unreal's
// CastScreenSpaceRay): samples in batches of 4, point-sampled at the nearest mip of a level that
// climbs two increments per batch, a hit where the ray is behind the cell's furthest surface by
// less than twice its tolerance. One implementation for every screen-space tracer and for both
// backends (FP_HD): SSGI and SSR set their rays up with screenRayOrigin and screenRaySteps
// (InitScreenSpaceRay, §4.5) and march them with marchHzb, each with its own tolerance, jitter
// and level schedule; SSR also asks for the interpolated hit (§4.6).
#include "foundation/Camera.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/PlaneView.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace fp {

/// Mips of an HZB a march can read: a 2¹⁶-texel-wide mip 0 is far beyond any capture.
constexpr int kMaxHzbMips = 16;

/// The furthest HZB as the march reads it (device Z, one plane per mip).
struct HzbView {
    PlaneView mips[kMaxHzbMips];
    int mipCount = 0;
};

/// The view of a host Texture or a DeviceTexture holding an HZB (at most kMaxHzbMips are read).
template <class TextureT>
HzbView hzbViewOf(const TextureT& hzb) {
    HzbView v;
    v.mipCount = hzb.mipCount() < kMaxHzbMips ? hzb.mipCount() : kMaxHzbMips;
    for (int m = 0; m < v.mipCount; ++m)
        v.mips[m] = viewOf(hzb.mip(m).plane(0));
    return v;
}

/// 2^−m exactly (m in 0…126), without a division: the march scales by it at every sample. I: int
/// or int lanes (LaneFloat.h), each lane its own m.
template <class I>
FP_HD inline auto inversePowerOfTwoOf(I m) {
    return floatFromBits((I(127) - m) << 23);
}
FP_HD inline float inversePowerOfTwo(int m) { return inversePowerOfTwoOf(m); }

/// Point sampling with an explicit fractional level: the nearest mip (algorithms §2, §13.10).
template <class T>
FP_HD inline IntOf<T> nearestMipOf(T level, int mipCount) {
    return floorToIntOf(level + 0.5f, 0, mipCount - 1);
}
FP_HD inline int nearestMip(float level, int mipCount) { return nearestMipOf(level, mipCount); }

/// Position in "half-resolution pixel" units: HZB mip 0 and reduced-colour mip 0 both have one
/// texel per 2×2 full-resolution pixels, so mip m texel = floor(h / 2^m) for either chain.
/// T: float, or float lanes (one ray a lane).
template <class T>
struct RayPointT {
    T hx, hy, z;  // half-res pixels, device Z
};
using RayPoint = RayPointT<float>;

/// A ray's march, set up: sample k lies at origin + step·k.
template <class T>
struct RayStepsT {
    RayPointT<T> origin, step;
    T tolerance;
};
using RaySteps = RayStepsT<float>;

/// What every screen-space ray of a frame shares: the camera, the HZB and the march's length.
struct ScreenRayFrame {
    CameraView cam;
    HzbView hzb;
    int steps;          //!< samples per ray (a multiple of 4)
    float invSteps;     //!< 1/steps
    float halfW, halfH;  //!< half the frame's size: the march's "half-res pixel" units
    float fx, fy, cx, cy;  //!< the projection's scale and centre, as float
};

/// Fills the camera part of `g` for a `width` × `height` frame.
inline void bindScreenRayCamera(ScreenRayFrame& g, const CameraView& cam, int width, int height) {
    g.cam = cam;
    g.halfW = 0.5f * float(width);
    g.halfH = 0.5f * float(height);
    g.fx = float(cam.fx);
    g.fy = float(cam.fy);
    g.cx = float(cam.cx);
    g.cy = float(cam.cy);
}

/// Where a pixel's rays start (algorithms §4.5): its screen position, device Z (and that of twice
/// its depth, for the tolerance), the jitter of its first sample and the start in march units.
struct ScreenRayOrigin {
    double depth;
    float sx, sy, z0, zTwice, stepOffset;
    RayPoint start;
};

/// The origin of full-resolution pixel (px, py) at view depth `d`, jittered by `stepOffset`.
FP_HD inline ScreenRayOrigin screenRayOrigin(const ScreenRayFrame& g, int px, int py, double d,
                                             float stepOffset) {
    ScreenRayOrigin p;
    p.depth = d;
    p.sx = float(g.cam.screenX(px));
    p.sy = float(g.cam.screenY(py));
    p.z0 = float(g.cam.deviceZFromDepth(d));
    p.zTwice = float(g.cam.deviceZFromDepth(2.0 * d));
    p.stepOffset = stepOffset;
    p.start = {(p.sx * 0.5f + 0.5f) * g.halfW, (0.5f - p.sy * 0.5f) * g.halfH, p.z0};
    return p;
}

/// algorithms §4.5 (InitScreenSpaceRay) for view-space direction L (x right, y up, z forward):
/// the end point of a ray as long as the pixel is deep, projected, then rescaled so the end lies
/// exactly on the screen border (extends short rays); the tolerance T = max(|ΔZ|, (Z − Z(2·depth))·k)
/// for the whole ray, k = `toleranceScale` (2 for SSGI, 4 for SSR). False for a ray straight
/// along the view axis: a miss. T: float, or float lanes (a ray a lane; the mask says which).
template <class T>
FP_HD inline MaskOf<T> screenRaySteps(const ScreenRayFrame& g, const ScreenRayOrigin& p,
                                      const Vec3T<T>& L, float toleranceScale, RayStepsT<T>& r) {
    const T w = maxLike(1.0f + L.z, T(1e-6f));
    const T ex = (p.sx + g.fx * L.x + g.cx * L.z) / w;
    const T ey = (p.sy + g.fy * L.y + g.cy * L.z) / w;
    const T ez = toFloat(deviceZFromDepthOf(g.cam.projectionZScale(), g.cam.projectionZOffset(),
                                            p.depth * toDouble(w)));
    T stepX = ex - p.sx, stepY = ey - p.sy, stepZ = ez - p.z0;
    T fit = T(std::numeric_limits<float>::infinity());
    fit = ifThenElse(stepX > 0.0f, minLike(fit, (1.0f - p.sx) / stepX), fit);
    fit = ifThenElse(stepX < 0.0f, minLike(fit, (-1.0f - p.sx) / stepX), fit);
    fit = ifThenElse(stepY > 0.0f, minLike(fit, (1.0f - p.sy) / stepY), fit);
    fit = ifThenElse(stepY < 0.0f, minLike(fit, (-1.0f - p.sy) / stepY), fit);
    const MaskOf<T> traced = isFiniteOf(fit);
    if (!anyLane(traced))
        return traced;
    stepX = stepX * fit;
    stepY = stepY * fit;
    stepZ = stepZ * fit;
    r.tolerance = maxLike(absOf(stepZ), T((p.z0 - p.zTwice) * toleranceScale)) * g.invSteps;
    r.step = {stepX * 0.5f * g.halfW * g.invSteps, -stepY * 0.5f * g.halfH * g.invSteps,
              stepZ * g.invSteps};
    r.origin = {p.start.hx + r.step.hx * p.stepOffset, p.start.hy + r.step.hy * p.stepOffset,
                p.start.z + r.step.z * p.stepOffset};
    return traced;
}

/// The point `time` samples along a ray (sample k at time k).
template <class T>
FP_HD inline RayPointT<T> rayPointAt(const RayStepsT<T>& r, T time) {
    return {r.origin.hx + r.step.hx * time, r.origin.hy + r.step.hy * time,
            r.origin.z + r.step.z * time};
}

/// Furthest device Z of the cell of mip view `cells` under (hx, hy) in half-res pixels scaled
/// by `scale` = 2^−mip, clamped to the mip (the GPU's clamp addressing).
template <class T>
FP_HD inline T hzbCell(const PlaneView& cells, float scale, T hx, T hy) {
    return gatherAt(cells, floorToIntOf(hx * scale, 0, cells.width - 1),
                    floorToIntOf(hy * scale, 0, cells.height - 1));
}

/// Marches `steps` samples (a multiple of 4) with the level rising `levelStep` per pair of
/// samples from 1. Returns the first sample behind the furthest surface of its cell by less than
/// 2·tolerance (−1: a miss) and leaves `level` at the mip level the ray reached. With `hitTime`,
/// also SSR's hit (§4.6): between the last sample before the hit (k − 1; the origin for k = 1,
/// its difference taken as 0) and the hit k, where the linear depth differences cross,
/// k − 1 + saturate(d₀/(d₀ − d₁)) (left as it was on a miss).
/// T: float, or float lanes marching the rays of `active` together: every ray's level follows the
/// same schedule, so a batch reads the same two mips in every lane, and a lane drops out after
/// the batch of its hit; the march ends when every lane has.
template <class T>
FP_HD inline T marchHzb(const HzbView& hzb,
                        const RayStepsT<T>& r,
                        int steps,
                        float levelStep,
                        T& level,
                        unsigned& hzbSamples,
                        T* hitTime = nullptr,
                        MaskOf<T> active = MaskOf<T>(true)) {
    float batchLevel = 1.0f;  // every marching lane's level
    level = T(batchLevel);
    T hitSample = T(-1.0f);
    T lastDiff = T(0.0f);
    MaskOf<T> marching = active;
    for (int batch = 0; batch * 4 < steps && anyLane(marching); ++batch) {
        // A batch's first two samples read the mip nearest `level`, its last two the one nearest
        // `level + levelStep`: each mip view is read once per pair.
        const int mips[2] = {nearestMip(batchLevel, hzb.mipCount),
                             nearestMip(batchLevel + levelStep, hzb.mipCount)};
        for (int pair = 0; pair < 2; ++pair) {
            const PlaneView cells = hzb.mips[mips[pair]];
            const float scale = inversePowerOfTwo(mips[pair]);
            for (int j = 0; j < 2; ++j) {
                const int k = batch * 4 + pair * 2 + j + 1;
                const T rz = r.origin.z + r.step.z * float(k);
                const T hz = hzbCell(cells, scale, r.origin.hx + r.step.hx * float(k),
                                     r.origin.hy + r.step.hy * float(k));
                const T diff = rz - hz;
                // A sky cell (device Z 0) is never hit: a ray extended past the point at
                // infinity would otherwise "hit" it [framepass guard].
                const MaskOf<T> hit = marching & (hitSample < 0.0f) & (hz > 0.0f) &
                                      (absOf(diff + r.tolerance) < r.tolerance);
                if (hitTime && anyLane(hit)) {
                    const T d0 = lastDiff, d1 = diff;
                    *hitTime = ifThenElse(
                        hit, float(k - 1) + ifThenElse(d0 - d1 != 0.0f, saturateOf(d0 / (d0 - d1)), T(0.0f)),
                        *hitTime);
                }
                hitSample = ifThenElse(hit, T(float(k)), hitSample);
                lastDiff = ifThenElse(hitSample < 0.0f, diff, lastDiff);
            }
        }
        hzbSamples += 4u * unsigned(countLanes(marching));
        batchLevel += 2.0f * levelStep;
        level = ifThenElse(marching, T(batchLevel), level);
        marching = marching & (hitSample < 0.0f);
    }
    return hitSample;
}

}  // namespace fp
