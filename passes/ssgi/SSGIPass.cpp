#include "passes/ssgi/SSGIPass.h"

#include "passes/common/GBuffer.h"
#include "passes/core/Error.h"
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
    return std::clamp(int(std::floor(level + 0.5f)), 0, mipCount - 1);
}

// Position in "half-resolution pixel" units: HZB mip 0 and reduced-colour mip 0 both have one
// texel per 2×2 full-resolution pixels, so mip m texel = floor(h / 2^m) for either chain.
struct RayPoint {
    float hx, hy, z;  // half-res pixels, device Z
};
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
    const Texture& hzb = *ctx.input(kFurthestHzb);
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

    const SSGIQuality q = qualityTable(mParams.quality);
    const uint32_t frameMod8 = ue::frameIndexMod8(frame.number);
    const float invSteps = 1.0f / float(q.steps);
    const float levelStep = 8.0f * invSteps;  // reference §4.6: (8/N)·Roughness, Roughness = 1
    const int hzbMips = hzb.mipCount();
    const float halfW = 0.5f * float(W), halfH = 0.5f * float(H);
    // Largest valid reduced-colour texel per mip (reference §3.4 ReducedColorUVMax).
    int reducedMaxX[kReducedMips], reducedMaxY[kReducedMips];
    for (int m = 0; m < kReducedMips; ++m) {
        reducedMaxX[m] = std::max(0, int(std::ceil(halfW / float(1 << m))) - 1);
        reducedMaxY[m] = std::max(0, int(std::ceil(halfH / float(1 << m))) - 1);
    }
    const float fx = float(cam.fx), fy = float(cam.fy), cx = float(cam.cx), cy = float(cam.cy);

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
                const Vec3d nw(gbuffer::worldNormalAt(normal, px, py));
                const Vec3f nView =
                    quantiseNormal(Vec3f{float(dot(nw, cam.right)), float(dot(nw, cam.up)),
                                         float(dot(nw, cam.forward))});
                const float sx = float(cam.screenX(px)), sy = float(cam.screenY(py));
                const float z0 = float(cam.deviceZFromDepth(d));
                // reference §4.5: tolerance T = max(|ΔZ|, (Z − Z(2·depth))·k) for the whole ray.
                const float zTwice = float(cam.deviceZFromDepth(2.0 * d));
                const float stepOffset =
                    ue::interleavedGradientNoise(float(x) + 0.5f, float(y) + 0.5f, frameMod8) +
                    kStepOffsetBias;
                const RayPoint start{(sx * 0.5f + 0.5f) * halfW, (0.5f - sy * 0.5f) * halfH, z0};

                float sum[3] = {0, 0, 0};
                int hits = 0, measuredHits = 0;
                double distanceSum = 0.0;
                for (int r = 0; r < q.rays; ++r) {
                    const Vec3f L = rayDirection(nView, x, y, frameMod8, r, q.rays);
                    // End point of a ray as long as the pixel is deep, projected (reference §4.5).
                    const float w = std::max(1.0f + L.z, 1e-6f);
                    const float ex = (sx + fx * L.x + cx * L.z) / w;
                    const float ey = (sy + fy * L.y + cy * L.z) / w;
                    const float ez = float(cam.deviceZFromDepth(d * double(w)));
                    float stepX = ex - sx, stepY = ey - sy, stepZ = ez - z0;
                    // Rescale so the end lies exactly on the screen border (extends short rays).
                    float fit = std::numeric_limits<float>::infinity();
                    if (stepX > 0.0f)
                        fit = std::min(fit, (1.0f - sx) / stepX);
                    if (stepX < 0.0f)
                        fit = std::min(fit, (-1.0f - sx) / stepX);
                    if (stepY > 0.0f)
                        fit = std::min(fit, (1.0f - sy) / stepY);
                    if (stepY < 0.0f)
                        fit = std::min(fit, (-1.0f - sy) / stepY);
                    ++rays;
                    if (!std::isfinite(fit))
                        continue;  // straight along the view axis: a miss
                    stepX *= fit;
                    stepY *= fit;
                    stepZ *= fit;
                    const float tolerance =
                        std::max(std::fabs(stepZ), (z0 - zTwice) * kToleranceScale) * invSteps;
                    const RayPoint step{stepX * 0.5f * halfW * invSteps,
                                        -stepY * 0.5f * halfH * invSteps, stepZ * invSteps};
                    const RayPoint origin{start.hx + step.hx * stepOffset,
                                          start.hy + step.hy * stepOffset,
                                          start.z + step.z * stepOffset};
                    // March in batches of 4 samples; two mip increments per batch (§4.6).
                    float level = 1.0f;
                    int hitSample = -1;
                    for (int batch = 0; batch * 4 < q.steps && hitSample < 0; ++batch) {
                        for (int j = 0; j < 4; ++j) {
                            const int k = batch * 4 + j + 1;
                            const int mip = nearestMip(j < 2 ? level : level + levelStep, hzbMips);
                            const float scale = 1.0f / float(1 << mip);
                            const float hx = origin.hx + step.hx * float(k);
                            const float hy = origin.hy + step.hy * float(k);
                            const float rz = origin.z + step.z * float(k);
                            const float hz = hzb.mip(mip).plane(0).clampedAt(
                                int(std::floor(hx * scale)), int(std::floor(hy * scale)));
                            const float diff = rz - hz;
                            // Behind the furthest surface of the cell by less than 2t (§4.6).
                            // A sky cell (device Z 0) is never hit: a ray extended past the point
                            // at infinity would otherwise "hit" it [framepass guard].
                            if (hitSample < 0 && hz > 0.0f &&
                                std::fabs(diff + tolerance) < tolerance)
                                hitSample = k;
                        }
                        hzbSamples += 4;
                        level += 2.0f * levelStep;
                    }
                    if (hitSample < 0)
                        continue;
                    const RayPoint hit{origin.hx + step.hx * float(hitSample),
                                       origin.hy + step.hy * float(hitSample),
                                       origin.z + step.z * float(hitSample)};
                    // Last frame's colour at the level the ray reached (point, nearest mip).
                    const int mip = nearestMip(level, kReducedMips);
                    const float scale = 1.0f / float(1 << mip);
                    const int rx = std::clamp(int(std::floor(hit.hx * scale)), 0, reducedMaxX[mip]);
                    const int ry = std::clamp(int(std::floor(hit.hy * scale)), 0, reducedMaxY[mip]);
                    const Image& rc = reduced.mip(mip);
                    const float c[3] = {rc.plane(0).at(rx, ry), rc.plane(1).at(rx, ry),
                                        rc.plane(2).at(rx, ry)};
                    // Karis weighting (reference §4.7), undone after the mean.
                    const float karis = 1.0f / (1.0f + ue::luma(c[0], c[1], c[2]));
                    for (int ch = 0; ch < 3; ++ch)
                        sum[ch] += c[ch] * karis;
                    ++hits;
                    if (hitDistance) {
                        const double hd = cam.depthFromDeviceZ(hit.z);
                        if (std::isfinite(hd)) {
                            const double hsx = hit.hx / halfW * 2.0 - 1.0;
                            const double hsy = 1.0 - hit.hy / halfH * 2.0;
                            const Vec3d a{(sx - cx) * d / fx, (sy - cy) * d / fy, d};
                            const Vec3d b{(hsx - cx) * hd / fx, (hsy - cy) * hd / fy, hd};
                            distanceSum += std::sqrt(dot(b - a, b - a));
                            ++measuredHits;
                        }
                    }
                }
                const float invRays = 1.0f / float(q.rays);
                float mean[3] = {sum[0] * invRays, sum[1] * invRays, sum[2] * invRays};
                const float inverseKaris = 1.0f / (1.0f - ue::luma(mean[0], mean[1], mean[2]));
                for (int ch = 0; ch < 3; ++ch)
                    diffuse.image().plane(ch).at(x, y) =
                        mean[ch] * inverseKaris * mParams.indirectLightingColorScale;
                const float hitFraction = float(hits) * invRays;
                ao.image().plane(0).at(x, y) = 1.0f - hitFraction;
                if (hitMask)
                    hitMask->image().plane(0).at(x, y) = hitFraction;
                if (hitDistance && measuredHits > 0)
                    hitDistance->image().plane(0).at(x, y) = float(distanceSum / measuredHits);
            }
        ctx.addWork("pixels", traced);
        ctx.addWork("skippedPixels", skipped);
        ctx.addWork("rays", rays);
        ctx.addWork("hzbSamples", hzbSamples);
    });
}

}  // namespace fp
