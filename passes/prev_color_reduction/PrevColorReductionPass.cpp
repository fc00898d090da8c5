#include "passes/prev_color_reduction/PrevColorReductionPass.h"

#include "passes/core/Error.h"
#include "passes/core/Tiles.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {
constexpr const char* kDepth = "depth";
constexpr const char* kVelocity = "velocity";
constexpr const char* kPrevColor = "prevColor";
constexpr const char* kPrevDepth = "prevDepth";
constexpr const char* kHistory = "history";
constexpr const char* kFurthestHzb = "furthestHzb";
constexpr const char* kColor = "color";
constexpr const char* kAlpha = "alpha";

// reference §3.2 step 8: saturate(1 − (d_ref − d)²/R²). Sky against sky keeps its weight (the two
// are the same "surface" at infinity); sky against geometry is a leak and gets none [inferred].
float depthWeight(double dRef, double d, double radius) {
    const bool refSky = std::isinf(dRef), sky = std::isinf(d);
    if (refSky || sky)
        return refSky && sky ? 1.0f : 0.0f;
    const double diff = dRef - d;
    return saturate(float(1.0 - diff * diff / (radius * radius)));
}

float bilinear(const Plane& p, float u, float v) {
    // u, v in pixels with centres at +0.5, clamp addressing.
    const float x = u - 0.5f, y = v - 0.5f;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float fx = x - x0, fy = y - y0;
    return (p.clampedAt(x0, y0) * (1 - fx) + p.clampedAt(x0 + 1, y0) * fx) * (1 - fy) +
           (p.clampedAt(x0, y0 + 1) * (1 - fx) + p.clampedAt(x0 + 1, y0 + 1) * fx) * fy;
}

float sanitize(float v) {
    return std::isfinite(v) && v > 0.0f ? v : 0.0f;
}
}  // namespace

float PrevColorReductionPass::vignette(float sx, float sy) {
    const float cx = saturate(std::fabs(sx) * 5.0f - 4.0f);
    const float cy = saturate(std::fabs(sy) * 5.0f - 4.0f);
    return saturate(1.0f - (cx * cx + cy * cy));
}

ParamSpec<PrevColorReductionParams> PrevColorReductionPass::paramSpec() {
    ParamSpec<PrevColorReductionParams> s;
    s.add("leakFree", &Params::leakFree,
          "reproject previous colour + depth with leak-free weights (true) or bilinear TAA "
          "history (false) (reference §3.1)")
        .cvar("r.SSGI.LeakFreeReprojection");
    s.add("preExposureCorrection", &Params::preExposureCorrection,
          "PreExposure(current)/PreExposure(previous) applied to the previous colour")
        .range(0.0, 1e6);
    s.add("removeSky", &Params::removeSky,
          "zero colour whose current depth exceeds skyDistance (UE5 behaviour; 4.27 keeps it)");
    s.add("skyDistance", &Params::skyDistance, "Unreal's SSGI sky distance, scene units")
        .range(0.0, 1e30);
    return s;
}

PassIO PrevColorReductionPass::describe() const {
    PassIO io;
    io.inputs = {
        {.name = kDepth,
         .channels = {"Z"},
         .captureDefault = "SceneDepth",
         .doc = "current linear depth"},
        {.name = kVelocity,
         .channels = {"X", "Y"},
         .optional = true,
         .doc = "optional per-pixel motion; camera reprojection when unbound"},
        {.name = kFurthestHzb,
         .channels = {"Z"},
         .doc = "furthest HZB: reference depth of the lower mips"},
    };
    if (mParams.leakFree) {
        io.inputs.push_back({.name = kPrevColor,
                             .channels = {"R", "G", "B"},
                             .kind = PortKind::Color,
                             .captureDefault = "PrevSceneColor",
                             .doc = "last frame's scene colour"});
        io.inputs.push_back({.name = kPrevDepth,
                             .channels = {"Z"},
                             .captureDefault = "PrevSceneDepth",
                             .doc = "last frame's linear depth"});
    } else {
        io.inputs.push_back({.name = kHistory,
                             .channels = {"R", "G", "B"},
                             .kind = PortKind::Color,
                             .captureDefault = "TAAHistory",
                             .doc = "last frame's TAA history"});
    }
    io.outputs = {
        {.name = kColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "reduced colour, premultiplied by the leak-free weight, 5 mips"},
        {.name = kAlpha, .channels = {"A"}, .doc = "accumulated leak-free weight, 5 mips"}};
    io.needsCamera = true;
    return io;
}

std::vector<Extent> PrevColorReductionPass::mipExtents(Extent frame) {
    auto roundUp16 = [](int v) { return (v + 15) / 16 * 16; };
    return mipChain({roundUp16((frame.width + 1) / 2), roundUp16((frame.height + 1) / 2)},
                    kMipCount);
}

std::vector<Extent> PrevColorReductionPass::outputExtents(std::string_view, Extent frame) const {
    return mipExtents(frame);
}

void PrevColorReductionPass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    FP_CHECK(frame.camera.previous || ctx.input(kVelocity),
             "the capture has no previous camera and no velocity: cannot reproject last frame");
    const CameraView& cam = frame.camera.current;
    const CameraView& prev = frame.camera.previous ? *frame.camera.previous : cam;
    const Plane& depth = ctx.input(kDepth)->image().plane(0);
    const Texture* velocity = ctx.input(kVelocity);
    const Image& prevColor = ctx.input(mParams.leakFree ? kPrevColor : kHistory)->image();
    const Plane* prevDepth = mParams.leakFree ? &ctx.input(kPrevDepth)->image().plane(0) : nullptr;
    const Texture& hzb = *ctx.input(kFurthestHzb);
    const int W = depth.width(), H = depth.height();
    const auto extents = mipExtents({W, H});
    // Both outputs are computed together (alpha is the weight the colour is premultiplied by).
    Texture& color = ctx.output(kColor, extents);
    Texture* alphaOut = ctx.isRequested(kAlpha) ? &ctx.output(kAlpha, extents) : nullptr;
    const bool leakFree = mParams.leakFree;
    // Offset of this eye from last frame's, so previous positions land in this frame's
    // camera-relative space without touching absolute coordinates.
    const Vec3d eyeDelta = prev.position - cam.position;
    // reference §3.2: R = 100 × (pixel world radius at depth d).
    auto radius = [&](double d) { return 100.0 * cam.pixelRadiusAtDepth(d); };

    // Per mip-0/1 texel: premultiplied colour, weight, and the reference (max) depth that the
    // next reduction level weighs its children against.
    std::vector<Image> levels;  // R G B A D per mip
    for (int m = 0; m < kMipCount; ++m)
        levels.emplace_back(extents[m].width, extents[m].height,
                            std::vector<std::string>{"R", "G", "B", "A", "D"});

    // --- pass 1: full-resolution reprojection, reduced to mip 0 --------------------------------
    auto reproject = [&](int px, int py, float out[4]) {
        const double d = depth.at(px, py);
        const double sx = cam.screenX(px), sy = cam.screenY(py);
        double pu, pv;  // previous position, continuous pixels
        if (velocity) {
            pu = px + 0.5 + velocity->image().plane(0).at(px, py);
            pv = py + 0.5 + velocity->image().plane(1).at(px, py);
        } else {
            // Sky reprojects by rotation only: a far point along the pixel's ray.
            const Vec3d p = std::isinf(d) ? cam.translatedFromPixel(px, py, 1.0) * 1e12
                                          : cam.translatedFromPixel(px, py, d);
            const auto proj = prev.projectOffset(p, cam.position);
            pu = proj.px;
            pv = proj.py;
        }
        const double psx = pu / W * 2.0 - 1.0, psy = 1.0 - pv / H * 2.0;
        float rgb[3], w = 1.0f;
        if (!leakFree) {
            for (int c = 0; c < 3; ++c)
                rgb[c] = bilinear(prevColor.plane(c), float(pu), float(pv));
        } else {
            // Clamp to the bilinear-safe rect, then point-sample colour and depth.
            const int qx = std::clamp(int(std::floor(pu)), 0, W - 1);
            const int qy = std::clamp(int(std::floor(pv)), 0, H - 1);
            for (int c = 0; c < 3; ++c)
                rgb[c] = prevColor.plane(c).at(qx, qy);
            const double pd = prevDepth->at(qx, qy);
            if (std::isinf(d) || std::isinf(pd)) {
                w = std::isinf(d) && std::isinf(pd) ? 1.0f : 0.0f;
            } else {
                const Vec3d pCur = cam.translatedFromPixel(px, py, d);
                const Vec3d pPrev = prev.translatedFromPixel(qx, qy, pd) + eyeDelta;
                const Vec3d diff = pCur - pPrev;
                const double r = radius(d);
                w = saturate(float(1.0 - dot(diff, diff) / (r * r)));
            }
        }
        float scale = w * mParams.preExposureCorrection *
                      std::min(vignette(float(sx), float(sy)), vignette(float(psx), float(psy)));
        if (mParams.removeSky && d > mParams.skyDistance)
            scale = 0.0f;
        for (int c = 0; c < 3; ++c)
            out[c] = sanitize(rgb[c]) * scale;
        out[3] = leakFree ? w * std::min(vignette(float(sx), float(sy)),
                                         vignette(float(psx), float(psy)))
                          : 1.0f;
    };

    // Reduces 2×2 children (colour, weight, depth) into one texel (reference §3.2 step 8).
    auto reduce = [&](const float child[4][5], float out[5]) {
        double dRef = child[0][4];
        for (int k = 1; k < 4; ++k)
            dRef = std::max(dRef, double(child[k][4]));
        for (int c = 0; c < 4; ++c)
            out[c] = 0.0f;
        for (int k = 0; k < 4; ++k) {
            // Plain path: box average. Leak-free: weighted sum divided by 4, not by Σweight,
            // so partial coverage darkens (as Unreal does).
            const float wk = leakFree ? depthWeight(dRef, child[k][4], radius(dRef)) : 1.0f;
            for (int c = 0; c < 4; ++c)
                out[c] += child[k][c] * wk * 0.25f;
        }
        out[4] = float(dRef);
    };

    const Extent e0 = extents[0];
    forEachTile(e0.width, e0.height, [&](const Tile& t) {
        uint64_t pixels = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                float child[4][5], out[5];
                bool any = false;
                for (int k = 0; k < 4; ++k) {
                    const int px = 2 * x + (k & 1), py = 2 * y + (k >> 1);
                    if (px >= W || py >= H) {
                        // Outside the view rect: Unreal never writes these; they hold nothing.
                        for (int c = 0; c < 4; ++c)
                            child[k][c] = 0.0f;
                        child[k][4] = depth.clampedAt(px, py);
                        continue;
                    }
                    reproject(px, py, child[k]);
                    child[k][4] = depth.at(px, py);
                    any = true;
                    ++pixels;
                }
                reduce(child, out);
                if (!any)
                    std::fill(out, out + 4, 0.0f);
                for (int c = 0; c < 5; ++c)
                    levels[0].plane(c).at(x, y) = out[c];
            }
        ctx.addWork("pixels", pixels);
    });

    auto reduceLevel = [&](int m) {
        const Image& src = levels[m - 1];
        Image& dst = levels[m];
        forEachTile(dst.width(), dst.height(), [&](const Tile& t) {
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) {
                    float child[4][5], out[5];
                    for (int k = 0; k < 4; ++k)
                        for (int c = 0; c < 5; ++c)
                            child[k][c] = src.plane(c).clampedAt(2 * x + (k & 1), 2 * y + (k >> 1));
                    reduce(child, out);
                    for (int c = 0; c < 5; ++c)
                        dst.plane(c).at(x, y) = out[c];
                }
        });
    };
    reduceLevel(1);

    // --- pass 2: mip 2 from mip 1 against the furthest HZB, then mips 3–4 ----------------------
    {
        const Image& src = levels[1];
        Image& dst = levels[2];
        const int hzbMip2 = std::min(2, hzb.mipCount() - 1);
        const int hzbMip1 = std::min(1, hzb.mipCount() - 1);
        auto hzbDepth = [&](int mip, int x, int y) {
            return cam.depthFromDeviceZ(hzb.mip(mip).plane(0).clampedAt(x, y));
        };
        forEachTile(dst.width(), dst.height(), [&](const Tile& t) {
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) {
                    float out[5] = {0, 0, 0, 0, 0};
                    const double dRef = leakFree ? hzbDepth(hzbMip2, x, y) : 0.0;
                    for (int k = 0; k < 4; ++k) {
                        const int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1);
                        // Plain path: one bilinear tap at the centre of the four = their mean.
                        const float wk =
                            leakFree ? depthWeight(dRef, hzbDepth(hzbMip1, cx, cy), radius(dRef))
                                     : 1.0f;
                        for (int c = 0; c < 4; ++c)
                            out[c] += src.plane(c).clampedAt(cx, cy) * 0.25f * wk;
                    }
                    out[4] = leakFree ? float(dRef) : src.plane(4).clampedAt(2 * x, 2 * y);
                    for (int c = 0; c < 5; ++c)
                        dst.plane(c).at(x, y) = out[c];
                }
        });
    }
    reduceLevel(3);
    reduceLevel(4);

    for (int m = 0; m < kMipCount; ++m) {
        for (int c = 0; c < 3; ++c) {
            const Plane& from = levels[m].plane(c);
            Plane& to = color.mip(m).plane(c);
            for (int y = 0; y < from.height(); ++y)
                std::copy(from.row(y), from.row(y) + from.width(), to.row(y));
        }
        if (alphaOut) {
            const Plane& from = levels[m].plane(3);
            Plane& to = alphaOut->mip(m).plane(0);
            for (int y = 0; y < from.height(); ++y)
                std::copy(from.row(y), from.row(y) + from.width(), to.row(y));
        }
    }
}

}  // namespace fp
