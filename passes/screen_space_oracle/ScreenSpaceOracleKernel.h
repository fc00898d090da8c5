#pragma once
// The screen-space oracle's per-pixel work, written once for both backends:
// ScreenSpaceOraclePass::execute runs it with CpuPixels, its .cu file with CudaPixels. Three
// sweeps: each pixel's tangent plane; the colour a ray that hits each pixel gathers (last frame's,
// where that pixel's surface was); the rays.
#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Random.h"
#include "foundation/ShadingModel.h"
#include "framework/Pass.h"
#include "reference/ScatterLobe.h"
#include "screenspace/GBuffer.h"
#include "screenspace/MaterialViews.h"
#include "screenspace/Reprojection.h"
#include "shading/BRDF.h"

#include <cmath>
#include <cstdint>

namespace fp::screen_space_oracle {

inline constexpr uint32_t kSeed = 0x4F52434Cu;  // "ORCL"
inline constexpr const char* kColor = "color";
inline constexpr const char* kDiffuse = "diffuse";
inline constexpr const char* kSpecular = "specular";
inline constexpr const char* kHitFraction = "hitFraction";
inline constexpr const char* kAo = "ao";
inline constexpr const char* kAoWithinRadius = "aoWithinRadius";
// A ray that leaves the camera runs to 10⁴ × its pixel's depth: on screen it is then within a
// ten-thousandth of its vanishing point.
constexpr float kFarFactor = 1e4f;
// Samples this much (relative) behind a tangent plane count as behind it: rays that leave a plane
// at a grazing angle stay in front of their own plane's neighbours despite float rounding.
constexpr float kPlaneBias = 1e-4f;

/// Work counted per pixel, in this order.
enum Counter { kTraced, kSkipped, kRays, kSteps, kCounterCount };

/// A pixel's surface as the march compares samples with it: its tangent plane in view space. With
/// n the unit normal and p the pixel centre's position, the plane's depth under screen point
/// (u, v) is n·p / n·r(u, v), r the view ray with z = 1; n·r is affine in (u, v), so 1/depth is
/// a·u + b·v + c, no division a sample. `inverseDepth` is 1/the stored depth (0 for sky).
struct TangentPlane {
    float a = 0, b = 0, c = 0, inverseDepth = 0;

    /// 1/depth of the plane under (u, v); the stored depth's where the plane is edge-on there or
    /// extrapolates past half or twice the stored depth (a silhouette pixel).
    FP_HD float inverseDepthAt(float u, float v) const {
        const float w = a * u + b * v + c;
        return w > 0.5f * inverseDepth && w < 2.0f * inverseDepth ? w : inverseDepth;
    }
};

struct March {
    int pixel = -1;      //!< the pixel whose surface the ray hit (−1: none on screen)
    float distance = 0;  //!< from the ray's origin, scene units
};

/// What every ray of the frame reads. View space: x right, y up, z = depth (Camera.h).
struct ScreenSpace {
    int width, height;
    float thickness, nearPlane, fx, fy, cx, cy;
    TangentPlane* planes;  //!< width × height, built by buildPlane before any march

    /// View-space position of the surface at pixel (x, y) and depth d.
    FP_HD Vec3f position(int x, int y, float d) const {
        const float sx = (float(x) + 0.5f) / float(width) * 2.0f - 1.0f;
        const float sy = 1.0f - (float(y) + 0.5f) / float(height) * 2.0f;
        return {(sx - cx) * d / fx, (sy - cy) * d / fy, d};
    }

    /// Pixel (x, y)'s tangent plane (left at zero on sky).
    FP_HD void buildPlane(const CameraView& cam, const PlaneView& depth, const PlaneView (&normal)[3], int x,
                          int y) const {
        const float d = depth.at(x, y);
        if (!std::isfinite(d)) return;
        const Vec3d nw(Vec3f{normal[0].at(x, y), normal[1].at(x, y), normal[2].at(x, y)});
        const Vec3f n = normalize(Vec3f{float(dot(nw, cam.right)), float(dot(nw, cam.up)), float(dot(nw, cam.forward))});
        // n·r = n.x·(2u/W − 1 − cx)/fx + n.y·(1 − 2v/H − cy)/fy + n.z, over n·p.
        const float inp = 1.0f / dot(n, position(x, y, d));
        TangentPlane& t = planes[y * width + x];
        t.a = 2.0f * n.x / (fx * float(width)) * inp;
        t.b = -2.0f * n.y / (fy * float(height)) * inp;
        t.c = (n.x * (-1.0f - cx) / fx + n.y * (1.0f - cy) / fy + n.z) * inp;
        t.inverseDepth = 1.0f / d;
    }

    FP_HD void project(const Vec3f& p, float& u, float& v) const {
        u = (fx * p.x / p.z + cx + 1.0f) * 0.5f * float(width);
        v = (1.0f - (fy * p.y / p.z + cy)) * 0.5f * float(height);
    }

    /// Marches the ray p0 + t·L (view space) from pixel (px, py) in half-pixel steps until the
    /// screen's edge; `steps` counts the samples taken.
    FP_HD March march(int px, int py, const Vec3f& p0, const Vec3f& L, unsigned long long& steps) const {
        float tEnd = kFarFactor * p0.z;
        if (L.z < 0.0f) {  // stop at the near plane
            const float toNear = (p0.z - nearPlane) / -L.z;
            tEnd = toNear < tEnd ? toNear : tEnd;
        }
        const Vec3f p1 = p0 + L * tEnd;
        float u0, v0, u1, v1;
        project(p0, u0, v0);
        project(p1, u1, v1);
        const float du = u1 - u0, dv = v1 - v0, len = std::sqrt(du * du + dv * dv);
        if (!(len > 0.5f)) return {};
        // Screen position and 1/z are both linear in s ∈ [0, 1]; clip s to the screen.
        float sEnd = 1.0f;
        auto clip = [&](float s) { sEnd = s < sEnd ? s : sEnd; };  // std::min(sEnd, s)
        if (du > 0.0f) clip((float(width) - u0) / du);
        if (du < 0.0f) clip(-u0 / du);
        if (dv > 0.0f) clip((float(height) - v0) / dv);
        if (dv < 0.0f) clip(-v0 / dv);
        const float w0 = 1.0f / p0.z, w1 = 1.0f / p1.z, ds = 0.5f / len;
        const int n = int(sEnd / ds);
        int taken = 0, lastPixel = py * width + px;
        TangentPlane plane;
        March hit;
        float wStep = w0;  // the ray's 1/depth at the sample before
        for (int k = 1; k <= n; ++k) {
            const float s = float(k) * ds;
            const float u = u0 + du * s, v = v0 + dv * s;
            const int iv = int(v), iu = int(u);
            const int pixel = (iv < 0 ? 0 : (iv > height - 1 ? height - 1 : iv)) * width +
                              (iu < 0 ? 0 : (iu > width - 1 ? width - 1 : iu));
            if (pixel == py * width + px) continue;
            ++taken;
            // Half-pixel steps land in the pixel of the step before about half the time.
            if (pixel != lastPixel) plane = planes[pixel];
            lastPixel = pixel;
            // A hit: the ray is behind the surface here (depth beyond it: 1/depth below its; sky
            // has 0, never), and was at most `thickness` behind it one step ago, so a ray that
            // crosses a surface between two samples (nearly along the view axis, a half-pixel
            // step can be deep) still meets it.
            const float w = w0 + (w1 - w0) * s;
            const float wSurface = plane.inverseDepthAt(u, v);
            const bool behind = w * (1.0f + kPlaneBias) < wSurface;
            const float wBefore = wStep;
            wStep = w;
            if (behind && 1.0f / wBefore - 1.0f / wSurface < thickness) {
                // The ray's point at s (perspective-correct) and its distance from the origin.
                const Vec3f p = (p0 * (w0 * (1.0f - s)) + p1 * (w1 * s)) * (1.0f / w);
                hit = {pixel, length(p - p0)};
                break;
            }
        }
        steps += (unsigned long long)taken;
        return hit;
    }
};

FP_HD inline float sanitized(float v) { return std::isfinite(v) && v > 0.0f ? v : 0.0f; }

/// Everything the sweeps read and write. Absent outputs have null data.
struct Frame {
    CameraView cam, previous;
    ScreenSpace screen;
    MaterialViews m;
    PlaneView color[3];
    VelocityView velocity;
    Vec3f* hitColor;  //!< width × height: last frame's colour where each pixel's surface was
    PlaneSpan diffuse[3], specular[3], hitFraction, ao, aoWithinRadius;
    bool wantDiffuse;
    int rays;
    float inverseRays, aoRadius;
    uint32_t frameKey;
    Vec3f right, up, forward;
};

/// Last frame's colour where pixel (x, y)'s surface was: what a ray that hits the pixel gathers.
FP_HD inline void hitColorPixel(const Frame& f, int x, int y) {
    const double d = f.m.depth.at(x, y);
    if (!std::isfinite(d)) return;
    const PreviousPixel p = reprojectPixelAtDepth(f.cam, x, y, d, f.velocity, f.previous);
    if (!p.onScreen({f.screen.width, f.screen.height})) return;
    const int u = int(p.u), v = int(p.v);
    f.hitColor[y * f.screen.width + x] = {sanitized(f.color[0].at(u, v)), sanitized(f.color[1].at(u, v)),
                                          sanitized(f.color[2].at(u, v))};
}

/// What one lobe's rays gathered: Σ weight/pdf × the colour at each hit (the cosine lobe's
/// weight/pdf is exactly 1), the hits, and those closer than aoRadius.
struct LobeSum {
    Vec3f radiance;
    int hits = 0, near = 0;
};

FP_HD inline LobeSum gather(const Frame& f, const ScatterLobe& lobe, int x, int y, const Vec3f& p0, Rng& rng,
                            unsigned long long* counts) {
    LobeSum sum;
    for (int r = 0; r < f.rays && lobe.active(); ++r) {
        const float c = rng.nextFloat(), u = rng.nextFloat(), v = rng.nextFloat();
        Vec3f L;
        if (!lobe.sample(c, u, v, L)) continue;
        const LobeValue lv = lobe.evaluate(L);
        if (!(lv.pdf > 0.0f)) continue;
        ++counts[kRays];
        const Vec3f Lview{dot(L, f.right), dot(L, f.up), dot(L, f.forward)};
        const March m = f.screen.march(x, y, p0, Lview, counts[kSteps]);
        if (m.pixel < 0) continue;
        sum.radiance += lv.weight * (1.0f / lv.pdf) * f.hitColor[m.pixel];
        ++sum.hits;
        sum.near += m.distance < f.aoRadius ? 1 : 0;
    }
    return sum;
}

/// Pixel (x, y): skipped (unlit or sky) or its cosine rays (when a diffuse-side output is read)
/// and its GGX rays (when the specular is) traced, the outputs written.
FP_HD inline void oraclePixel(const Frame& f, int x, int y, unsigned long long* counts) {
    const float d = f.m.depth.at(x, y);
    if (!isLitSurface(d, f.m.shadingModel.at(x, y))) {
        if (f.ao) f.ao.at(x, y) = 1.0f;
        if (f.aoWithinRadius) f.aoWithinRadius.at(x, y) = 1.0f;
        ++counts[kSkipped];
        return;
    }
    ++counts[kTraced];
    const Vec3f p0 = f.screen.position(x, y, d);
    // The surface as the truth tracer's lobes see it (world axes, camera-relative).
    SurfacePoint s;
    s.position = Vec3f(f.cam.translatedFromPixel(x, y, d));
    s.normal = s.geometricNormal =
        normalize(Vec3f{f.m.normal[0].at(x, y), f.m.normal[1].at(x, y), f.m.normal[2].at(x, y)});
    s.toViewer = normalize(-s.position);
    s.brdf = SurfaceBRDF::fromMaterial({f.m.baseColor[0].at(x, y), f.m.baseColor[1].at(x, y), f.m.baseColor[2].at(x, y)},
                                       f.m.metallic.at(x, y), f.m.specular.at(x, y), f.m.roughness.at(x, y));
    Rng rng = Rng::fromKey(f.frameKey, x, y);
    if (f.wantDiffuse) {
        const LobeSum g = gather(f, ScatterLobe(ScatterLobe::Kind::Cosine, s), x, y, p0, rng, counts);
        if (f.diffuse[0])
            for (int c = 0; c < 3; ++c) f.diffuse[c].at(x, y) = g.radiance[c] * f.inverseRays;
        if (f.hitFraction) f.hitFraction.at(x, y) = float(g.hits) * f.inverseRays;
        if (f.ao) f.ao.at(x, y) = 1.0f - float(g.hits) * f.inverseRays;
        if (f.aoWithinRadius) f.aoWithinRadius.at(x, y) = 1.0f - float(g.near) * f.inverseRays;
    }
    if (f.specular[0]) {
        const LobeSum g = gather(f, ScatterLobe(ScatterLobe::Kind::Specular, s), x, y, p0, rng, counts);
        for (int c = 0; c < 3; ++c) f.specular[c].at(x, y) = g.radiance[c] / float(f.rays);
    }
}

/// The whole pass through `ports` on `pixels`, its work reported to `ctx`.
template <class Ports, class Pixels>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, int rays, float thicknessCm,
         float aoRadiusMetres) {
    const FrameInfo& frame = ctx.frame();
    const CameraView& cam = frame.camera.current;
    const int W = frame.extent.width, H = frame.extent.height;
    const std::vector<Extent> extent = {frame.extent};
    Frame f{};
    f.cam = cam;
    // Without last frame's camera (and no motion vectors) the scene is taken as still.
    f.previous = frame.camera.previous ? *frame.camera.previous : cam;
    f.m = bindMaterialViews(ports, MaterialExtras::None);  // the truth's lobes read neither
    const auto& color = ports.input(kColor)->image();
    FP_CHECK(color.width() == W && color.height() == H,
             "screen_space_oracle: color is {}×{}, the frame {}×{}: it reads last frame's colour at "
             "full resolution", color.width(), color.height(), W, H);
    for (int c = 0; c < 3; ++c) f.color[c] = viewOf(color.plane(c));
    f.velocity = velocityViewOf(ports.input(gbuffer::kVelocity));

    const double cm = frame.camera.sceneUnitsPerMeter / 100.0;
    const auto planeMemory = ports.template scratchArray<TangentPlane>(std::size_t(W) * H);
    const auto hitColorMemory = ports.template scratchArray<Vec3f>(std::size_t(W) * H);
    f.screen = {W, H, float(thicknessCm * cm), float(cam.nearPlane), float(cam.fx), float(cam.fy),
                float(cam.cx), float(cam.cy), planeMemory.get()};
    f.hitColor = hitColorMemory.get();
    f.aoRadius = float(aoRadiusMetres * frame.camera.sceneUnitsPerMeter);
    f.rays = rays;
    f.inverseRays = 1.0f / float(rays);
    f.frameKey = Rng::frameKey(frame.number, kSeed);
    f.right = Vec3f(cam.right);
    f.up = Vec3f(cam.up);
    f.forward = Vec3f(cam.forward);

    // Only what is read is traced: the cosine rays feed diffuse, hitFraction and the two AOs; the
    // GGX rays feed specular.
    if (auto* t = ports.outputIfRequested(kDiffuse, extent))
        for (int c = 0; c < 3; ++c) f.diffuse[c] = spanOf(t->image().plane(c));
    if (auto* t = ports.outputIfRequested(kSpecular, extent))
        for (int c = 0; c < 3; ++c) f.specular[c] = spanOf(t->image().plane(c));
    if (auto* t = ports.outputIfRequested(kHitFraction, extent)) f.hitFraction = spanOf(t->image().plane(0));
    if (auto* t = ports.overwriteIfRequested(kAo, extent)) f.ao = spanOf(t->image().plane(0));
    if (auto* t = ports.overwriteIfRequested(kAoWithinRadius, extent)) f.aoWithinRadius = spanOf(t->image().plane(0));
    f.wantDiffuse = f.diffuse[0] || f.hitFraction || f.ao || f.aoWithinRadius;

    // Planes and gathered colours start at zero (sky, and pixels off last frame's screen).
    pixels.template forEach<0>(
        W, H,
        [=] FP_HD(int x, int y, WorkCounts<0>&) {
            f.screen.planes[y * W + x] = TangentPlane{};
            f.hitColor[y * W + x] = Vec3f{};
            f.screen.buildPlane(f.cam, f.m.depth, f.m.normal, x, y);
            hitColorPixel(f, x, y);
        },
        "screen_space_oracle planes");
    const auto counts = pixels.template forEach<kCounterCount>(
        W, H, [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& n) { oraclePixel(f, x, y, n.value); },
        "screen_space_oracle");
    ctx.addWork("pixels", counts[kTraced]);
    ctx.addWork("skippedPixels", counts[kSkipped]);
    ctx.addWork("rays", counts[kRays]);
    ctx.addWork("marchSteps", counts[kSteps]);
}

}  // namespace fp::screen_space_oracle
