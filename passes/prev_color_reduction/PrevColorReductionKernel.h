#pragma once
// The previous-colour reduction's per-pixel work (algorithms §3.2–3.3), written once for
// PrevColorReductionPass::execute and PrevColorReductionPass.cu.
#include "screenspace/GBuffer.h"
#include "screenspace/Reprojection.h"
#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "passes/prev_color_reduction/PrevColorReductionPass.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace fp::prev_color {

inline constexpr const char* kPrevColor = "prevColor";
inline constexpr const char* kPrevDepth = "prevDepth";
inline constexpr const char* kHistory = "history";
inline constexpr const char* kFurthestHzb = "furthestHzb";
inline constexpr const char* kColor = "color";
inline constexpr const char* kAlpha = "alpha";

// algorithms §3.2 step 8: saturate(1 − (d_ref − d)²/R²). Sky against sky keeps its weight (the two
// are the same "surface" at infinity); sky against geometry is a leak and gets none [inferred].
FP_HD inline float depthWeight(double dRef, double d, double radius) {
    const bool refSky = std::isinf(dRef), sky = std::isinf(d);
    if (refSky || sky)
        return refSky && sky ? 1.0f : 0.0f;
    const double diff = dRef - d;
    return saturate(float(1.0 - diff * diff / (radius * radius)));
}

// u, v in pixels with centres at +0.5, clamp addressing.
FP_HD inline float bilinear(const PlaneView& p, float u, float v) {
    const float x = u - 0.5f, y = v - 0.5f;
    // Clamp addressing: anything beyond one texel outside reads the edge (NaN reads the corner).
    const int x0 = floorToInt(x, -1, p.width), y0 = floorToInt(y, -1, p.height);
    const float fx = std::isfinite(x) ? std::clamp(x - float(x0), 0.0f, 1.0f) : 0.0f;
    const float fy = std::isfinite(y) ? std::clamp(y - float(y0), 0.0f, 1.0f) : 0.0f;
    return (p.clampedAt(x0, y0) * (1 - fx) + p.clampedAt(x0 + 1, y0) * fx) * (1 - fy) +
           (p.clampedAt(x0, y0 + 1) * (1 - fx) + p.clampedAt(x0 + 1, y0 + 1) * fx) * fy;
}

FP_HD inline float sanitize(float v) {
    return std::isfinite(v) && v > 0.0f ? v : 0.0f;
}

// algorithms §3.2: R = 100 × (pixel world radius at depth d).
FP_HD inline double leakFreeRadius(const CameraView& cam, double d) {
    return 100.0 * cam.pixelRadiusAtDepth(d);
}

/// What reprojecting one full-resolution pixel reads.
struct ReprojectInputs {
    CameraView cam;
    CameraView prev;  //!< this frame's camera when only velocity is known
    PlaneView depth;
    VelocityView velocity;
    PlaneView prevColor[3];  //!< previous scene colour (leak-free) or TAA history
    PlaneView prevDepth;     //!< leak-free only
    bool leakFree, removeSky;
    float preExposureCorrection, skyDistance;
};

// algorithms §3.2 steps 1–7 for full-resolution pixel (px, py): last frame's colour at its previous
// position, premultiplied by the leak-free weight, pre-exposure and the screen-edge vignette, and
// that weight × vignette in out[3] (1 on the plain path).
FP_HD inline void reprojectColor(const ReprojectInputs& in, int px, int py, float out[4]) {
    const CameraView& cam = in.cam;
    const int W = in.depth.width, H = in.depth.height;
    const bool leakFree = in.leakFree;
    const double d = in.depth.at(px, py);
    const double sx = cam.screenX(px), sy = cam.screenY(py);
    const PreviousPixel prev = reprojectPixelAtDepth(cam, px, py, d, in.velocity, in.prev);
    const double pu = prev.u, pv = prev.v;
    const double psx = pu / W * 2.0 - 1.0, psy = 1.0 - pv / H * 2.0;
    float rgb[3], w = 1.0f;
    if (!leakFree) {
        for (int c = 0; c < 3; ++c)
            rgb[c] = bilinear(in.prevColor[c], float(pu), float(pv));
    } else {
        // Clamp to the bilinear-safe rect, then point-sample colour and depth.
        const int qx = floorToInt(pu, 0, W - 1);
        const int qy = floorToInt(pv, 0, H - 1);
        for (int c = 0; c < 3; ++c)
            rgb[c] = in.prevColor[c].at(qx, qy);
        const double pd = in.prevDepth.at(qx, qy);
        if (std::isinf(d) || std::isinf(pd)) {
            w = std::isinf(d) && std::isinf(pd) ? 1.0f : 0.0f;
        } else {
            // Last frame's position offset by its eye's move, so it lands in this frame's
            // camera-relative space without touching absolute coordinates.
            const Vec3d pCur = cam.translatedFromPixel(px, py, d);
            const Vec3d pPrev =
                in.prev.translatedFromPixel(qx, qy, pd) + (in.prev.position - cam.position);
            const Vec3d diff = pCur - pPrev;
            const double r = leakFreeRadius(cam, d);
            w = saturate(float(1.0 - dot(diff, diff) / (r * r)));
        }
    }
    const float fade = std::min(vignette(float(sx), float(sy)), vignette(float(psx), float(psy)));
    float scale = w * in.preExposureCorrection * fade;
    if (in.removeSky && d > in.skyDistance)
        scale = 0.0f;
    for (int c = 0; c < 3; ++c)
        out[c] = sanitize(rgb[c]) * scale;
    out[3] = leakFree ? w * fade : 1.0f;
}

// Reduces 2×2 children (colour, weight, depth) into one texel (algorithms §3.2 step 8).
FP_HD inline void reduceChildren(const CameraView& cam,
                                 bool leakFree,
                                 const float child[4][5],
                                 float out[5]) {
    double dRef = child[0][4];
    for (int k = 1; k < 4; ++k)
        dRef = std::max(dRef, double(child[k][4]));
    for (int c = 0; c < 4; ++c)
        out[c] = 0.0f;
    for (int k = 0; k < 4; ++k) {
        // Plain path: box average. Leak-free: weighted sum divided by 4, not by Σweight,
        // so partial coverage darkens (as Unreal does).
        const float wk =
            leakFree ? depthWeight(dRef, child[k][4], leakFreeRadius(cam, dRef)) : 1.0f;
        for (int c = 0; c < 4; ++c)
            out[c] += child[k][c] * wk * 0.25f;
    }
    out[4] = float(dRef);
}

/// One mip level as the reductions read and write it: R G B A D planes.
struct Level {
    PlaneSpan plane[5];
};

template <class TextureT>
Level levelOf(TextureT& t, int mip) {
    Level l;
    for (int c = 0; c < 5; ++c)
        l.plane[c] = spanOf(t.mip(mip).plane(c));
    return l;
}

// Pass 1, mip-0 texel (x, y): its 2×2 full-resolution pixels reprojected and reduced. Returns
// the number of pixels inside the view.
FP_HD inline int reduceFullResolutionTexel(const ReprojectInputs& in, const Level& mip0, int x,
                                           int y) {
    const int W = in.depth.width, H = in.depth.height;
    float child[4][5], out[5];
    int inside = 0;
    for (int k = 0; k < 4; ++k) {
        const int px = 2 * x + (k & 1), py = 2 * y + (k >> 1);
        if (px >= W || py >= H) {
            // Outside the view rect: Unreal never writes these; they hold nothing.
            for (int c = 0; c < 4; ++c)
                child[k][c] = 0.0f;
            child[k][4] = in.depth.clampedAt(px, py);
            continue;
        }
        reprojectColor(in, px, py, child[k]);
        child[k][4] = in.depth.at(px, py);
        ++inside;
    }
    reduceChildren(in.cam, in.leakFree, child, out);
    if (inside == 0)
        for (int c = 0; c < 4; ++c)
            out[c] = 0.0f;
    for (int c = 0; c < 5; ++c)
        mip0.plane[c].at(x, y) = out[c];
    return inside;
}

// Texel (x, y) of a level from the level above, 2×2 children at a time.
FP_HD inline void reduceLevelTexel(const CameraView& cam, bool leakFree, const Level& src,
                                   const Level& dst, int x, int y) {
    float child[4][5], out[5];
    for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 5; ++c)
            child[k][c] = viewOf(src.plane[c]).clampedAt(2 * x + (k & 1), 2 * y + (k >> 1));
    reduceChildren(cam, leakFree, child, out);
    for (int c = 0; c < 5; ++c)
        dst.plane[c].at(x, y) = out[c];
}

// Pass 2 (algorithms §3.3), texel (x, y) of mip 2 from mip 1: the reference depth and the
// children's depths read from the furthest HZB (mips 2 and 1) instead of the chain's own.
FP_HD inline void reduceAgainstHzbTexel(const CameraView& cam, bool leakFree, const PlaneView& hzb2,
                                        const PlaneView& hzb1, const Level& src, const Level& dst,
                                        int x, int y) {
    float out[5] = {0, 0, 0, 0, 0};
    const double dRef = leakFree ? cam.depthFromDeviceZ(hzb2.clampedAt(x, y)) : 0.0;
    for (int k = 0; k < 4; ++k) {
        const int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1);
        // Plain path: one bilinear tap at the centre of the four = their mean.
        const float wk = leakFree ? depthWeight(dRef, cam.depthFromDeviceZ(hzb1.clampedAt(cx, cy)),
                                                leakFreeRadius(cam, dRef))
                                  : 1.0f;
        for (int c = 0; c < 4; ++c)
            out[c] += viewOf(src.plane[c]).clampedAt(cx, cy) * 0.25f * wk;
    }
    out[4] = leakFree ? float(dRef) : viewOf(src.plane[4]).clampedAt(2 * x, 2 * y);
    for (int c = 0; c < 5; ++c)
        dst.plane[c].at(x, y) = out[c];
}

/// Texel (x, y) of mip m ≥ 1 from mip m − 1: against the HZB for mip 2 (algorithms §3.3), from
/// the level's own depths otherwise.
struct ReduceLevel {
    CameraView cam;
    bool leakFree, againstHzb;
    PlaneView hzb2, hzb1;
    Level src, dst;
    FP_HD void operator()(int x, int y, WorkCounts<0>&) const {
        if (againstHzb)
            reduceAgainstHzbTexel(cam, leakFree, hzb2, hzb1, src, dst, x, y);
        else
            reduceLevelTexel(cam, leakFree, src, dst, x, y);
    }
};

/// The whole pass on either backend (PerPixel.h): mip 0 from the reprojected pixels, mip 1 from
/// mip 0, mip 2 against the HZB, mips 3–4 from the level above; then the colour and the weight
/// copied out (both are computed together: alpha is what the colour is premultiplied by).
template <class Ports, class Pixels>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels,
         const PrevColorReductionParams& params) {
    const FrameInfo& frame = ctx.frame();
    const auto* velocity = ports.input(gbuffer::kVelocity);
    FP_CHECK(frame.camera.previous || velocity,
             "the capture has no previous camera and no velocity: cannot reproject last frame");
    const auto& depth = ports.input(gbuffer::kDepth)->image();
    const auto& prevColor = ports.input(params.leakFree ? kPrevColor : kHistory)->image();
    ReprojectInputs in{};
    in.cam = frame.camera.current;
    in.prev = frame.camera.previous ? *frame.camera.previous : frame.camera.current;
    in.depth = viewOf(depth.plane(0));
    in.velocity = velocityViewOf(velocity);
    for (int c = 0; c < 3; ++c)
        in.prevColor[c] = viewOf(prevColor.plane(c));
    if (params.leakFree)
        in.prevDepth = viewOf(ports.input(kPrevDepth)->image().plane(0));
    in.leakFree = params.leakFree;
    in.removeSky = params.removeSky;
    in.preExposureCorrection = params.preExposureCorrection;
    in.skyDistance = params.skyDistance;
    const auto& hzb = *ports.input(kFurthestHzb);
    const PlaneView hzb2 = viewOf(hzb.mip(std::min(2, hzb.mipCount() - 1)).plane(0));
    const PlaneView hzb1 = viewOf(hzb.mip(std::min(1, hzb.mipCount() - 1)).plane(0));
    const std::vector<Extent> extents =
        PrevColorReductionPass::mipExtents({depth.width(), depth.height()});

    // Per mip texel: premultiplied colour, weight, and the reference (max) depth that the next
    // reduction level weighs its children against.
    auto levels = ports.scratch(extents, {"R", "G", "B", "A", "D"});
    const CameraView cam = in.cam;
    const bool leakFree = params.leakFree;
    const Level l0 = levelOf(levels, 0);
    const auto inside = pixels.template forEach<1>(
        extents[0].width, extents[0].height,
        [=] FP_HD(int x, int y, WorkCounts<1>& c) {
            c.value[0] += reduceFullResolutionTexel(in, l0, x, y);
        },
        "prev_color_reduction");
    ctx.addWork("pixels", inside[0]);
    for (int m = 1; m < PrevColorReductionPass::kMipCount; ++m) {
        const ReduceLevel reduce{cam, leakFree, m == 2, hzb2, hzb1, levelOf(levels, m - 1),
                                 levelOf(levels, m)};
        pixels.template forEach<0>(extents[m].width, extents[m].height, reduce,
                                   "prev_color_reduction");
    }

    auto& color = ports.overwrite(kColor, extents);
    auto* alpha = ports.overwriteIfRequested(kAlpha, extents);
    for (int m = 0; m < PrevColorReductionPass::kMipCount; ++m) {
        const Level src = levelOf(levels, m);
        PlaneSpan dst[4];
        for (int c = 0; c < 3; ++c)
            dst[c] = spanOf(color.mip(m).plane(c));
        if (alpha)
            dst[3] = spanOf(alpha->mip(m).plane(0));
        pixels.template forEach<0>(
            extents[m].width, extents[m].height,
            [=] FP_HD(int x, int y, WorkCounts<0>&) {
                for (int c = 0; c < 4; ++c)
                    if (dst[c])
                        dst[c].at(x, y) = src.plane[c].at(x, y);
            },
            "prev_color_reduction");
    }
}

}  // namespace fp::prev_color
