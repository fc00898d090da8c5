#include "passes/prev_color_reduction/PrevColorReductionPass.h"

#include "passes/common/GBuffer.h"
#include "passes/common/Reprojection.h"
#include "passes/core/Error.h"
#include "passes/core/FloatToInt.h"
#include "passes/core/Tiles.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {
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
    // Clamp addressing: anything beyond one texel outside reads the edge (NaN reads the corner).
    const int x0 = floorToInt(x, -1, p.width()), y0 = floorToInt(y, -1, p.height());
    const float fx = std::isfinite(x) ? std::clamp(x - float(x0), 0.0f, 1.0f) : 0.0f;
    const float fy = std::isfinite(y) ? std::clamp(y - float(y0), 0.0f, 1.0f) : 0.0f;
    return (p.clampedAt(x0, y0) * (1 - fx) + p.clampedAt(x0 + 1, y0) * fx) * (1 - fy) +
           (p.clampedAt(x0, y0 + 1) * (1 - fx) + p.clampedAt(x0 + 1, y0 + 1) * fx) * fy;
}

float sanitize(float v) {
    return std::isfinite(v) && v > 0.0f ? v : 0.0f;
}

// reference §3.2: R = 100 × (pixel world radius at depth d).
double leakFreeRadius(const CameraView& cam, double d) {
    return 100.0 * cam.pixelRadiusAtDepth(d);
}

// What reprojecting one full-resolution pixel reads.
struct ReprojectInputs {
    const CameraView& cam;
    const CameraView& prev;  // this frame's camera when only velocity is known
    const Plane& depth;
    const Texture* velocity;
    const Image& prevColor;  // previous scene colour (leak-free) or TAA history
    const Plane* prevDepth;  // leak-free only
    const PrevColorReductionParams& params;
};

// Reference §3.2 steps 1–7 for full-resolution pixel (px, py): last frame's colour at its previous
// position, premultiplied by the leak-free weight, pre-exposure and the screen-edge vignette, and
// that weight × vignette in out[3] (1 on the plain path).
void reprojectColor(const ReprojectInputs& in, int px, int py, float out[4]) {
    const CameraView& cam = in.cam;
    const int W = in.depth.width(), H = in.depth.height();
    const bool leakFree = in.params.leakFree;
    const double d = in.depth.at(px, py);
    const double sx = cam.screenX(px), sy = cam.screenY(py);
    const PreviousPixel prev = reprojectPixelAtDepth(cam, px, py, d, in.velocity, in.prev);
    const double pu = prev.u, pv = prev.v;
    const double psx = pu / W * 2.0 - 1.0, psy = 1.0 - pv / H * 2.0;
    float rgb[3], w = 1.0f;
    if (!leakFree) {
        for (int c = 0; c < 3; ++c)
            rgb[c] = bilinear(in.prevColor.plane(c), float(pu), float(pv));
    } else {
        // Clamp to the bilinear-safe rect, then point-sample colour and depth.
        const int qx = floorToInt(pu, 0, W - 1);
        const int qy = floorToInt(pv, 0, H - 1);
        for (int c = 0; c < 3; ++c)
            rgb[c] = in.prevColor.plane(c).at(qx, qy);
        const double pd = in.prevDepth->at(qx, qy);
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
    const float fade = std::min(PrevColorReductionPass::vignette(float(sx), float(sy)),
                                PrevColorReductionPass::vignette(float(psx), float(psy)));
    float scale = w * in.params.preExposureCorrection * fade;
    if (in.params.removeSky && d > in.params.skyDistance)
        scale = 0.0f;
    for (int c = 0; c < 3; ++c)
        out[c] = sanitize(rgb[c]) * scale;
    out[3] = leakFree ? w * fade : 1.0f;
}

// Reduces 2×2 children (colour, weight, depth) into one texel (reference §3.2 step 8).
void reduceChildren(const CameraView& cam, bool leakFree, const float child[4][5], float out[5]) {
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

// Pass 1: every full-resolution pixel reprojected, reduced 2×2 into mip 0 (R G B A D).
void reduceFullResolution(PassContext& ctx, const ReprojectInputs& in, Image& mip0) {
    const int W = in.depth.width(), H = in.depth.height();
    forEachTile(mip0.width(), mip0.height(), [&](const Tile& t) {
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
                        child[k][4] = in.depth.clampedAt(px, py);
                        continue;
                    }
                    reprojectColor(in, px, py, child[k]);
                    child[k][4] = in.depth.at(px, py);
                    any = true;
                    ++pixels;
                }
                reduceChildren(in.cam, in.params.leakFree, child, out);
                if (!any)
                    std::fill(out, out + 4, 0.0f);
                for (int c = 0; c < 5; ++c)
                    mip0.plane(c).at(x, y) = out[c];
            }
        ctx.addWork("pixels", pixels);
    });
}

// One level of the chain from the level above, 2×2 children at a time.
void reduceLevel(const CameraView& cam, bool leakFree, const Image& src, Image& dst) {
    forEachTile(dst.width(), dst.height(), [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                float child[4][5], out[5];
                for (int k = 0; k < 4; ++k)
                    for (int c = 0; c < 5; ++c)
                        child[k][c] = src.plane(c).clampedAt(2 * x + (k & 1), 2 * y + (k >> 1));
                reduceChildren(cam, leakFree, child, out);
                for (int c = 0; c < 5; ++c)
                    dst.plane(c).at(x, y) = out[c];
            }
    });
}

// Pass 2 (reference §3.3): mip 2 from mip 1, the reference depth and the children's depths read
// from the furthest HZB instead of the chain's own.
void reduceAgainstHzb(const CameraView& cam,
                      bool leakFree,
                      const Texture& hzb,
                      const Image& src,
                      Image& dst) {
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
                    const float wk = leakFree ? depthWeight(dRef, hzbDepth(hzbMip1, cx, cy),
                                                            leakFreeRadius(cam, dRef))
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

void copyPlane(const Plane& from, Plane& to) {
    for (int y = 0; y < from.height(); ++y)
        std::copy(from.row(y), from.row(y) + from.width(), to.row(y));
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
        gbuffer::depthInput("current linear depth"),
        gbuffer::velocityInput("optional per-pixel motion; camera reprojection when unbound"),
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
    const Texture* velocity = ctx.input(gbuffer::kVelocity);
    FP_CHECK(frame.camera.previous || velocity,
             "the capture has no previous camera and no velocity: cannot reproject last frame");
    const CameraView& cam = frame.camera.current;
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const bool leakFree = mParams.leakFree;
    const ReprojectInputs in{cam,
                             frame.camera.previous ? *frame.camera.previous : cam,
                             depth,
                             velocity,
                             ctx.input(leakFree ? kPrevColor : kHistory)->image(),
                             leakFree ? &ctx.input(kPrevDepth)->image().plane(0) : nullptr,
                             mParams};
    const auto extents = mipExtents({depth.width(), depth.height()});

    // Per mip texel: premultiplied colour, weight, and the reference (max) depth that the next
    // reduction level weighs its children against.
    std::vector<Image> levels;  // R G B A D per mip
    for (int m = 0; m < kMipCount; ++m)
        levels.emplace_back(extents[m].width, extents[m].height,
                            std::vector<std::string>{"R", "G", "B", "A", "D"});
    reduceFullResolution(ctx, in, levels[0]);
    reduceLevel(cam, leakFree, levels[0], levels[1]);
    reduceAgainstHzb(cam, leakFree, *ctx.input(kFurthestHzb), levels[1], levels[2]);
    reduceLevel(cam, leakFree, levels[2], levels[3]);
    reduceLevel(cam, leakFree, levels[3], levels[4]);

    // Both outputs are computed together (alpha is the weight the colour is premultiplied by).
    Texture& color = ctx.output(kColor, extents);
    Texture* alpha = ctx.isRequested(kAlpha) ? &ctx.output(kAlpha, extents) : nullptr;
    for (int m = 0; m < kMipCount; ++m) {
        for (int c = 0; c < 3; ++c)
            copyPlane(levels[m].plane(c), color.mip(m).plane(c));
        if (alpha)
            copyPlane(levels[m].plane(3), alpha->mip(m).plane(0));
    }
}

}  // namespace fp
