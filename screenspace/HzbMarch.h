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

/// 2^−m exactly (m in 0…126), without a division: the march scales by it at every sample.
FP_HD inline float inversePowerOfTwo(int m) {
    return std::bit_cast<float>(uint32_t(127 - m) << 23);
}

/// Point sampling with an explicit fractional level: the nearest mip (algorithms §2, §13.10).
FP_HD inline int nearestMip(float level, int mipCount) {
    return floorToInt(level + 0.5f, 0, mipCount - 1);
}

/// Position in "half-resolution pixel" units: HZB mip 0 and reduced-colour mip 0 both have one
/// texel per 2×2 full-resolution pixels, so mip m texel = floor(h / 2^m) for either chain.
struct RayPoint {
    float hx, hy, z;  // half-res pixels, device Z
};

/// A ray's march, set up: sample k lies at origin + step·k.
struct RaySteps {
    RayPoint origin, step;
    float tolerance;
};

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
/// along the view axis: a miss.
FP_HD inline bool screenRaySteps(const ScreenRayFrame& g, const ScreenRayOrigin& p, const Vec3f& L,
                                 float toleranceScale, RaySteps& r) {
    const float w = std::max(1.0f + L.z, 1e-6f);
    const float ex = (p.sx + g.fx * L.x + g.cx * L.z) / w;
    const float ey = (p.sy + g.fy * L.y + g.cy * L.z) / w;
    const float ez = float(g.cam.deviceZFromDepth(p.depth * double(w)));
    float stepX = ex - p.sx, stepY = ey - p.sy, stepZ = ez - p.z0;
    float fit = std::numeric_limits<float>::infinity();
    if (stepX > 0.0f)
        fit = std::min(fit, (1.0f - p.sx) / stepX);
    if (stepX < 0.0f)
        fit = std::min(fit, (-1.0f - p.sx) / stepX);
    if (stepY > 0.0f)
        fit = std::min(fit, (1.0f - p.sy) / stepY);
    if (stepY < 0.0f)
        fit = std::min(fit, (-1.0f - p.sy) / stepY);
    if (!std::isfinite(fit))
        return false;
    stepX *= fit;
    stepY *= fit;
    stepZ *= fit;
    r.tolerance = std::max(std::fabs(stepZ), (p.z0 - p.zTwice) * toleranceScale) * g.invSteps;
    r.step = {stepX * 0.5f * g.halfW * g.invSteps, -stepY * 0.5f * g.halfH * g.invSteps,
              stepZ * g.invSteps};
    r.origin = {p.start.hx + r.step.hx * p.stepOffset, p.start.hy + r.step.hy * p.stepOffset,
                p.start.z + r.step.z * p.stepOffset};
    return true;
}

/// The point `time` samples along a ray (sample k at time k).
FP_HD inline RayPoint rayPointAt(const RaySteps& r, float time) {
    return {r.origin.hx + r.step.hx * time, r.origin.hy + r.step.hy * time,
            r.origin.z + r.step.z * time};
}

/// Furthest device Z of the cell of mip view `cells` under (hx, hy) in half-res pixels scaled
/// by `scale` = 2^−mip, clamped to the mip (the GPU's clamp addressing).
FP_HD inline float hzbCell(const PlaneView& cells, float scale, float hx, float hy) {
    return cells.at(floorToInt(hx * scale, 0, cells.width - 1),
                    floorToInt(hy * scale, 0, cells.height - 1));
}

/// Marches `steps` samples (a multiple of 4) with the level rising `levelStep` per pair of
/// samples from 1. Returns the first sample behind the furthest surface of its cell by less than
/// 2·tolerance (−1: a miss) and leaves `level` at the mip level the ray reached. With `hitTime`,
/// also SSR's hit (§4.6): between the last sample before the hit (k − 1; the origin for k = 1,
/// its difference taken as 0) and the hit k, where the linear depth differences cross,
/// k − 1 + saturate(d₀/(d₀ − d₁)).
FP_HD inline int marchHzb(const HzbView& hzb,
                          const RaySteps& r,
                          int steps,
                          float levelStep,
                          float& level,
                          unsigned& hzbSamples,
                          float* hitTime = nullptr) {
    level = 1.0f;
    int hitSample = -1;
    float lastDiff = 0.0f;
    for (int batch = 0; batch * 4 < steps && hitSample < 0; ++batch) {
        // A batch's first two samples read the mip nearest `level`, its last two the one nearest
        // `level + levelStep`: each mip view is read once per pair.
        int mips[2] = {nearestMip(level, hzb.mipCount), nearestMip(level + levelStep, hzb.mipCount)};
        for (int pair = 0; pair < 2; ++pair) {
            const PlaneView cells = hzb.mips[mips[pair]];
            const float scale = inversePowerOfTwo(mips[pair]);
            for (int j = 0; j < 2; ++j) {
                const int k = batch * 4 + pair * 2 + j + 1;
                const float rz = r.origin.z + r.step.z * float(k);
                const float hz = hzbCell(cells, scale, r.origin.hx + r.step.hx * float(k),
                                         r.origin.hy + r.step.hy * float(k));
                const float diff = rz - hz;
                // A sky cell (device Z 0) is never hit: a ray extended past the point at
                // infinity would otherwise "hit" it [framepass guard].
                if (hitSample < 0 && hz > 0.0f && std::fabs(diff + r.tolerance) < r.tolerance) {
                    hitSample = k;
                    if (hitTime) {
                        const float d0 = lastDiff, d1 = diff;
                        *hitTime = float(k - 1) + (d0 - d1 != 0.0f ? saturate(d0 / (d0 - d1)) : 0.0f);
                    }
                }
                if (hitSample < 0)
                    lastDiff = diff;
            }
        }
        hzbSamples += 4;
        level += 2.0f * levelStep;
    }
    return hitSample;
}

}  // namespace fp
