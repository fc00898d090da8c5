#include "passes/ssgi/SSGIPass.h"

#include "passes/common/GBuffer.h"
#include "passes/core/Error.h"
#include "passes/core/FloatToInt.h"
#include "passes/core/Sampling.h"
#include "passes/core/ShadingModel.h"
#include "passes/core/Tiles.h"
#include "passes/core/UnrealRandom.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fp {

namespace {
constexpr const char* kFurthestHzb = "furthestHzb";
constexpr const char* kReducedColor = "reducedColor";
constexpr const char* kDiffuse = "diffuse";
constexpr const char* kAo = "ao";
constexpr const char* kHitMask = "hitMask";
constexpr const char* kHitDistance = "hitDistance";

constexpr float kStepOffsetBias = -0.9f;  // reference §4.6: IGN − 0.9 for SSGI (−0.5 for SSR)
constexpr float kToleranceScale = 2.0f;   // reference §4.5: k = 2 for SSGI (4 for SSR)
constexpr int kReducedMips = 5;           // prev_color_reduction's chain (reference §3.1)

// The view-space normal goes through 8 bits per axis in Unreal's LDS (reference §4.3).
Vec3f quantiseNormal(const Vec3f& n) {
    auto q = [](float v) { return std::round((v * 0.5f + 0.5f) * 255.0f) / 255.0f * 2.0f - 1.0f; };
    return normalize(Vec3f{q(n.x), q(n.y), q(n.z)});
}

// Point sampling with an explicit fractional level: the nearest mip (reference §2, §13.10).
int nearestMip(float level, int mipCount) {
    return floorToInt(level + 0.5f, 0, mipCount - 1);
}

// Position in "half-resolution pixel" units: HZB mip 0 and reduced-colour mip 0 both have one
// texel per 2×2 full-resolution pixels, so mip m texel = floor(h / 2^m) for either chain.
struct RayPoint {
    float hx, hy, z;  // half-res pixels, device Z
};

// What every ray of the frame shares.
struct TraceSetup {
    const CameraView& cam;
    const Texture& hzb;
    const Texture& reduced;
    SSGIQuality q;
    uint32_t frameMod8;
    float invSteps, levelStep;
    float halfW, halfH;
    float fx, fy, cx, cy;
    // Largest valid reduced-colour texel per mip (reference §3.4 ReducedColorUVMax).
    int reducedMaxX[kReducedMips], reducedMaxY[kReducedMips];
};

TraceSetup makeSetup(const CameraView& cam,
                     const Texture& hzb,
                     const Texture& reduced,
                     const SSGIParams& params,
                     int64_t frame,
                     int W,
                     int H) {
    const SSGIQuality q = SSGIPass::qualityTable(params.quality);
    const float invSteps = 1.0f / float(q.steps);
    TraceSetup s{cam,
                 hzb,
                 reduced,
                 q,
                 ue::frameIndexMod8(frame),
                 invSteps,
                 8.0f * invSteps,  // reference §4.6: (8/N)·Roughness, Roughness = 1
                 0.5f * float(W),
                 0.5f * float(H),
                 float(cam.fx),
                 float(cam.fy),
                 float(cam.cx),
                 float(cam.cy),
                 {},
                 {}};
    for (int m = 0; m < kReducedMips; ++m) {
        s.reducedMaxX[m] = std::max(0, int(std::ceil(s.halfW / float(1 << m))) - 1);
        s.reducedMaxY[m] = std::max(0, int(std::ceil(s.halfH / float(1 << m))) - 1);
    }
    return s;
}

// The per-pixel start of every ray (reference §4.3–4.5).
struct PixelStart {
    double depth;
    Vec3f nView;  // quantised view-space normal
    float sx, sy, z0, zTwice, stepOffset;
    RayPoint start;
};

PixelStart
pixelStart(const TraceSetup& s, const Image& normal, int x, int y, int px, int py, double d) {
    const CameraView& cam = s.cam;
    const Vec3d nw(gbuffer::worldNormalAt(normal, px, py));
    PixelStart p;
    p.depth = d;
    p.nView = quantiseNormal(
        Vec3f{float(dot(nw, cam.right)), float(dot(nw, cam.up)), float(dot(nw, cam.forward))});
    p.sx = float(cam.screenX(px));
    p.sy = float(cam.screenY(py));
    p.z0 = float(cam.deviceZFromDepth(d));
    // reference §4.5: tolerance T = max(|ΔZ|, (Z − Z(2·depth))·k) for the whole ray.
    p.zTwice = float(cam.deviceZFromDepth(2.0 * d));
    p.stepOffset = ue::interleavedGradientNoise(float(x) + 0.5f, float(y) + 0.5f, s.frameMod8) +
                   kStepOffsetBias;
    p.start = {(p.sx * 0.5f + 0.5f) * s.halfW, (0.5f - p.sy * 0.5f) * s.halfH, p.z0};
    return p;
}

// A ray's march, set up: where sample k lies is origin + step·k.
struct RaySteps {
    RayPoint origin, step;
    float tolerance;
};

// Reference §4.5: the end point of a ray as long as the pixel is deep, projected, then rescaled
// so the end lies exactly on the screen border (extends short rays). False for a ray straight
// along the view axis: a miss.
bool raySteps(const TraceSetup& s, const PixelStart& p, const Vec3f& L, RaySteps& r) {
    const float w = std::max(1.0f + L.z, 1e-6f);
    const float ex = (p.sx + s.fx * L.x + s.cx * L.z) / w;
    const float ey = (p.sy + s.fy * L.y + s.cy * L.z) / w;
    const float ez = float(s.cam.deviceZFromDepth(p.depth * double(w)));
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
    r.tolerance = std::max(std::fabs(stepZ), (p.z0 - p.zTwice) * kToleranceScale) * s.invSteps;
    r.step = {stepX * 0.5f * s.halfW * s.invSteps, -stepY * 0.5f * s.halfH * s.invSteps,
              stepZ * s.invSteps};
    r.origin = {p.start.hx + r.step.hx * p.stepOffset, p.start.hy + r.step.hy * p.stepOffset,
                p.start.z + r.step.z * p.stepOffset};
    return true;
}

// Reference §4.6: the march in batches of 4 HZB samples, two mip increments per batch. Returns
// the first sample behind the furthest surface of its cell by less than 2t (−1: a miss) and
// leaves `level` at the mip level the ray reached.
int marchRay(const TraceSetup& s, const RaySteps& r, float& level, uint64_t& hzbSamples) {
    const int hzbMips = s.hzb.mipCount();
    level = 1.0f;
    int hitSample = -1;
    for (int batch = 0; batch * 4 < s.q.steps && hitSample < 0; ++batch) {
        for (int j = 0; j < 4; ++j) {
            const int k = batch * 4 + j + 1;
            const int mip = nearestMip(j < 2 ? level : level + s.levelStep, hzbMips);
            const float scale = 1.0f / float(1 << mip);
            const float hx = r.origin.hx + r.step.hx * float(k);
            const float hy = r.origin.hy + r.step.hy * float(k);
            const float rz = r.origin.z + r.step.z * float(k);
            const float hz = s.hzb.mip(mip).plane(0).clampedAt(
                floorToInt(hx * scale, -1, s.hzb.mip(mip).width()),
                floorToInt(hy * scale, -1, s.hzb.mip(mip).height()));
            const float diff = rz - hz;
            // A sky cell (device Z 0) is never hit: a ray extended past the point at infinity
            // would otherwise "hit" it [framepass guard].
            if (hitSample < 0 && hz > 0.0f && std::fabs(diff + r.tolerance) < r.tolerance)
                hitSample = k;
        }
        hzbSamples += 4;
        level += 2.0f * s.levelStep;
    }
    return hitSample;
}

// Last frame's colour where a ray hit, at the level it reached (point, nearest mip; §4.7).
void hitColor(const TraceSetup& s, const RayPoint& hit, float level, float c[3]) {
    const int mip = nearestMip(level, kReducedMips);
    const float scale = 1.0f / float(1 << mip);
    const int rx = floorToInt(hit.hx * scale, 0, s.reducedMaxX[mip]);
    const int ry = floorToInt(hit.hy * scale, 0, s.reducedMaxY[mip]);
    const Image& rc = s.reduced.mip(mip);
    c[0] = rc.plane(0).at(rx, ry);
    c[1] = rc.plane(1).at(rx, ry);
    c[2] = rc.plane(2).at(rx, ry);
}

// View-space distance from the pixel to a hit (debug output); false for a hit on the sky.
bool viewDistanceToHit(const TraceSetup& s,
                       const PixelStart& p,
                       const RayPoint& hit,
                       double& distance) {
    const double hd = s.cam.depthFromDeviceZ(hit.z);
    if (!std::isfinite(hd))
        return false;
    const double d = p.depth;
    const double hsx = hit.hx / s.halfW * 2.0 - 1.0;
    const double hsy = 1.0 - hit.hy / s.halfH * 2.0;
    const Vec3d a{(p.sx - s.cx) * d / s.fx, (p.sy - s.cy) * d / s.fy, d};
    const Vec3d b{(hsx - s.cx) * hd / s.fx, (hsy - s.cy) * hd / s.fy, hd};
    distance = std::sqrt(dot(b - a, b - a));
    return true;
}

// What one pixel's rays gathered.
struct PixelTrace {
    float diffuse[3];
    float hitFraction;
    int measuredHits;
    double distanceSum;
};

// Reference §4.4–4.8 for one traced pixel: every ray marched, hits gathering last frame's
// colour Karis-weighted (§4.7), the weighting undone after the mean.
PixelTrace tracePixel(const TraceSetup& s,
                      const PixelStart& p,
                      int x,
                      int y,
                      bool wantDistance,
                      uint64_t& rays,
                      uint64_t& hzbSamples) {
    float sum[3] = {0, 0, 0};
    int hits = 0;
    PixelTrace t{{0, 0, 0}, 0.0f, 0, 0.0};
    for (int r = 0; r < s.q.rays; ++r) {
        const Vec3f L = SSGIPass::rayDirection(p.nView, x, y, s.frameMod8, r, s.q.rays);
        RaySteps steps;
        ++rays;
        if (!raySteps(s, p, L, steps))
            continue;
        float level;
        const int hitSample = marchRay(s, steps, level, hzbSamples);
        if (hitSample < 0)
            continue;
        const RayPoint hit{steps.origin.hx + steps.step.hx * float(hitSample),
                           steps.origin.hy + steps.step.hy * float(hitSample),
                           steps.origin.z + steps.step.z * float(hitSample)};
        float c[3];
        hitColor(s, hit, level, c);
        const float karis = 1.0f / (1.0f + ue::luma(c[0], c[1], c[2]));
        for (int ch = 0; ch < 3; ++ch)
            sum[ch] += c[ch] * karis;
        ++hits;
        double distance;
        if (wantDistance && viewDistanceToHit(s, p, hit, distance)) {
            t.distanceSum += distance;
            ++t.measuredHits;
        }
    }
    const float invRays = 1.0f / float(s.q.rays);
    const float mean[3] = {sum[0] * invRays, sum[1] * invRays, sum[2] * invRays};
    const float inverseKaris = 1.0f / (1.0f - ue::luma(mean[0], mean[1], mean[2]));
    for (int ch = 0; ch < 3; ++ch)
        t.diffuse[ch] = mean[ch] * inverseKaris;
    t.hitFraction = float(hits) * invRays;
    return t;
}
}  // namespace

ParamSpec<SSGIParams> SSGIPass::paramSpec() {
    ParamSpec<SSGIParams> s;
    s.add("quality", &Params::quality,
          "1..4 → 4/8/16/32 rays per pixel and 8/8/8/12 steps per ray (reference §4.2)")
        .range(1, 4)
        .cvar("r.SSGI.Quality");
    s.add("halfRes", &Params::halfRes,
          "trace at half resolution (the top-left pixel of every 2×2 block); UE5 names the cvar "
          "r.DiffuseIndirect.HalfRes (default 1)")
        .cvar("r.SSGI.HalfRes")
        .cvar("r.DiffuseIndirect.HalfRes");
    s.add("indirectLightingColorScale", &Params::indirectLightingColorScale,
          "4.27 only: post-process IndirectLightingIntensity (× white IndirectLightingColor)")
        .range(0.0, 1e6);
    return s;
}

SSGIQuality SSGIPass::qualityTable(int quality) {
    static constexpr SSGIQuality kTable[] = {{4, 8}, {8, 8}, {16, 8}, {32, 12}};
    return kTable[std::clamp(quality, 1, 4) - 1];
}

Extent SSGIPass::traceExtent(Extent frame, bool halfRes) {
    return halfRes ? Extent{(frame.width + 1) / 2, (frame.height + 1) / 2} : frame;
}

PassIO SSGIPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit (0) pixels are skipped"),
        {.name = kFurthestHzb, .channels = {"Z"}, .doc = "furthest HZB (device Z)"},
        {.name = kReducedColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "last frame's colour, reprojected and reduced to 5 mips"},
    };
    io.outputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "mean incoming radiance of the rays (irradiance/π); 0 on skipped pixels"},
        {.name = kAo,
         .channels = {"Y"},
         .doc = "1 − fraction of rays that hit; 1 on skipped pixels"},
        {.name = kHitMask,
         .channels = {"Y"},
         .doc = "debug: fraction of rays that hit (0 on skipped pixels)"},
        {.name = kHitDistance,
         .channels = {"Y"},
         .doc = "debug: mean distance from the pixel to its rays' hits, scene units (0: no hit)"},
    };
    io.needsCamera = true;
    io.workUnit = "hzbSamples";
    return io;
}

std::vector<Extent> SSGIPass::outputExtents(std::string_view, Extent frame) const {
    return {traceExtent(frame, mParams.halfRes)};
}

Vec3f SSGIPass::rayDirection(const Vec3f& n,
                             int x,
                             int y,
                             uint32_t frameMod8,
                             int index,
                             int count) {
    const ue::Rand3 seed = ue::rand3DPCG16(x, y, int32_t(frameMod8));
    float e1, e2, dx, dy;
    ue::hammersley16(uint32_t(index), uint32_t(count), seed.x, seed.y, e1, e2);
    ue::concentricDisk(e1, e2, dx, dy);
    const float dz = std::sqrt(std::max(0.0f, 1.0f - dx * dx - dy * dy));
    Vec3f t, b;
    orthonormalBasis(n, t, b);
    return t * dx + b * dy + n * dz;
}

void SSGIPass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const CameraView& cam = frame.camera.current;
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Image& normal = ctx.input(gbuffer::kNormal)->image();
    const Plane& shadingModel = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Texture& reduced = *ctx.input(kReducedColor);
    FP_CHECK(reduced.mipCount() >= kReducedMips, "reducedColor has {} mips; SSGI needs {}",
             reduced.mipCount(), kReducedMips);
    const int W = depth.width(), H = depth.height();
    const Extent trace = traceExtent({W, H}, mParams.halfRes);
    const int toFull = mParams.halfRes ? 2 : 1;

    Texture& diffuse = ctx.output(kDiffuse, {trace});
    Texture& ao = ctx.output(kAo, {trace});
    Texture* hitMask = ctx.isRequested(kHitMask) ? &ctx.output(kHitMask, {trace}) : nullptr;
    Texture* hitDistance =
        ctx.isRequested(kHitDistance) ? &ctx.output(kHitDistance, {trace}) : nullptr;
    const TraceSetup setup =
        makeSetup(cam, *ctx.input(kFurthestHzb), reduced, mParams, frame.number, W, H);

    forEachTile(trace.width, trace.height, [&](const Tile& t) {
        uint64_t traced = 0, skipped = 0, rays = 0, hzbSamples = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const int px = std::min(x * toFull, W - 1), py = std::min(y * toFull, H - 1);
                const double d = depth.at(px, py);
                if (!isLitSurface(d, shadingModel.at(px, py))) {  // unlit and sky: not traced
                    ao.image().plane(0).at(x, y) = 1.0f;  // diffuse, hit mask, distance stay 0
                    ++skipped;
                    continue;
                }
                ++traced;
                const PixelStart start = pixelStart(setup, normal, x, y, px, py, d);
                const PixelTrace r =
                    tracePixel(setup, start, x, y, hitDistance != nullptr, rays, hzbSamples);
                for (int ch = 0; ch < 3; ++ch)
                    diffuse.image().plane(ch).at(x, y) =
                        r.diffuse[ch] * mParams.indirectLightingColorScale;
                ao.image().plane(0).at(x, y) = 1.0f - r.hitFraction;
                if (hitMask)
                    hitMask->image().plane(0).at(x, y) = r.hitFraction;
                if (hitDistance && r.measuredHits > 0)
                    hitDistance->image().plane(0).at(x, y) = float(r.distanceSum / r.measuredHits);
            }
        ctx.addWork("pixels", traced);
        ctx.addWork("skippedPixels", skipped);
        ctx.addWork("rays", rays);
        ctx.addWork("hzbSamples", hzbSamples);
    });
}

}  // namespace fp
