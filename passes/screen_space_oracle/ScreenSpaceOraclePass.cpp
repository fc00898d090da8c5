#include "passes/screen_space_oracle/ScreenSpaceOraclePass.h"

#include "screenspace/GBuffer.h"
#include "screenspace/Reprojection.h"
#include "foundation/Error.h"
#include "framework/PassPorts.h"
#include "foundation/Random.h"
#include "foundation/ShadingModel.h"
#include "foundation/Tiles.h"
#include "reference/ScatterLobe.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fp {

namespace {

constexpr uint32_t kSeedOracle = 0x4F52434Cu;  // "ORCL"
constexpr const char* kColor = "color";
constexpr const char* kDiffuse = "diffuse";
constexpr const char* kSpecularOut = "specular";
constexpr const char* kHitFraction = "hitFraction";
constexpr const char* kAo = "ao";
constexpr const char* kAoWithinRadius = "aoWithinRadius";
// A ray that leaves the camera runs to 10⁴ × its pixel's depth: on screen it is then within a
// ten-thousandth of its vanishing point.
constexpr float kFarFactor = 1e4f;
// Samples this much (relative) behind a tangent plane count as behind it: rays that leave a plane
// at a grazing angle stay in front of their own plane's neighbours despite float rounding.
constexpr float kPlaneBias = 1e-4f;

// A pixel's surface as the march compares samples with it: its tangent plane in view space. With
// n the unit normal and p the pixel centre's position, the plane's depth under screen point (u, v)
// is n·p / n·r(u, v), r the view ray with z = 1; n·r is affine in (u, v), so 1/depth is
// a·u + b·v + c, no division a sample. `inverseDepth` is 1/the stored depth (0 for sky).
struct TangentPlane {
    float a = 0, b = 0, c = 0, inverseDepth = 0;

    // 1/depth of the plane under (u, v); the stored depth's where the plane is edge-on there or
    // extrapolates past half or twice the stored depth (a silhouette pixel).
    float inverseDepthAt(float u, float v) const {
        const float w = a * u + b * v + c;
        return w > 0.5f * inverseDepth && w < 2.0f * inverseDepth ? w : inverseDepth;
    }
};

struct March {
    int pixel = -1;      // the pixel whose surface the ray hit (−1: none on screen)
    float distance = 0;  // from the ray's origin, scene units
};

// What every ray of the frame reads. View space: x right, y up, z = depth (Camera.h).
class ScreenSpace {
public:
    ScreenSpace(const CameraView& cam, const Plane& depth, const Image& normal, float thickness)
        : mW(cam.width), mH(cam.height), mThickness(thickness),
          mNear(float(cam.nearPlane)), mFx(float(cam.fx)), mFy(float(cam.fy)),
          mCx(float(cam.cx)), mCy(float(cam.cy)), mPlanes(std::size_t(mW) * mH) {
        forEachTile(mW, mH, [&](const Tile& t) {
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) {
                    const float d = depth.at(x, y);
                    if (!std::isfinite(d)) continue;
                    const Vec3d nw(gbuffer::worldNormalAt(normal, x, y));
                    const Vec3f n = normalize(Vec3f{float(dot(nw, cam.right)), float(dot(nw, cam.up)),
                                                    float(dot(nw, cam.forward))});
                    // n·r = n.x·(2u/W − 1 − cx)/fx + n.y·(1 − 2v/H − cy)/fy + n.z, over n·p.
                    const float inp = 1.0f / dot(n, position(x, y, d));
                    TangentPlane& t = mPlanes[std::size_t(y) * mW + x];
                    t.a = 2.0f * n.x / (mFx * float(mW)) * inp;
                    t.b = -2.0f * n.y / (mFy * float(mH)) * inp;
                    t.c = (n.x * (-1.0f - mCx) / mFx + n.y * (1.0f - mCy) / mFy + n.z) * inp;
                    t.inverseDepth = 1.0f / d;
                }
        });
    }

    /// View-space position of the surface at pixel (x, y) and depth d.
    Vec3f position(int x, int y, float d) const {
        const float sx = (float(x) + 0.5f) / float(mW) * 2.0f - 1.0f;
        const float sy = 1.0f - (float(y) + 0.5f) / float(mH) * 2.0f;
        return {(sx - mCx) * d / mFx, (sy - mCy) * d / mFy, d};
    }

    /// Marches the ray p0 + t·L (view space) from pixel (px, py) in half-pixel steps until the
    /// screen's edge; `steps` counts the samples taken.
    March march(int px, int py, const Vec3f& p0, const Vec3f& L, uint64_t& steps) const {
        float tEnd = kFarFactor * p0.z;
        if (L.z < 0.0f) tEnd = std::min(tEnd, (p0.z - mNear) / -L.z);  // stop at the near plane
        const Vec3f p1 = p0 + L * tEnd;
        float u0, v0, u1, v1;
        project(p0, u0, v0);
        project(p1, u1, v1);
        const float du = u1 - u0, dv = v1 - v0, len = std::sqrt(du * du + dv * dv);
        if (!(len > 0.5f)) return {};
        // Screen position and 1/z are both linear in s ∈ [0, 1]; clip s to the screen.
        float sEnd = 1.0f;
        if (du > 0.0f) sEnd = std::min(sEnd, (float(mW) - u0) / du);
        if (du < 0.0f) sEnd = std::min(sEnd, -u0 / du);
        if (dv > 0.0f) sEnd = std::min(sEnd, (float(mH) - v0) / dv);
        if (dv < 0.0f) sEnd = std::min(sEnd, -v0 / dv);
        const float w0 = 1.0f / p0.z, w1 = 1.0f / p1.z, ds = 0.5f / len;
        const int n = int(sEnd / ds);
        int taken = 0, lastPixel = py * mW + px;
        TangentPlane plane;
        March hit;
        float wStep = w0;  // the ray's 1/depth at the sample before
        for (int k = 1; k <= n; ++k) {
            const float s = float(k) * ds;
            const float u = u0 + du * s, v = v0 + dv * s;
            const int pixel = std::clamp(int(v), 0, mH - 1) * mW + std::clamp(int(u), 0, mW - 1);
            if (pixel == py * mW + px) continue;
            ++taken;
            // Half-pixel steps land in the pixel of the step before about half the time.
            if (pixel != lastPixel) plane = mPlanes[std::size_t(pixel)];
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
            if (behind && 1.0f / wBefore - 1.0f / wSurface < mThickness) {
                // The ray's point at s (perspective-correct) and its distance from the origin.
                const Vec3f p = (p0 * (w0 * (1.0f - s)) + p1 * (w1 * s)) * (1.0f / w);
                hit = {pixel, length(p - p0)};
                break;
            }
        }
        steps += uint64_t(taken);
        return hit;
    }

private:
    void project(const Vec3f& p, float& u, float& v) const {
        u = (mFx * p.x / p.z + mCx + 1.0f) * 0.5f * float(mW);
        v = (1.0f - (mFy * p.y / p.z + mCy)) * 0.5f * float(mH);
    }

    int mW, mH;
    float mThickness, mNear, mFx, mFy, mCx, mCy;
    std::vector<TangentPlane> mPlanes;
};

float sanitized(float v) { return std::isfinite(v) && v > 0.0f ? v : 0.0f; }

}  // namespace

ParamSpec<ScreenSpaceOracleParams> ScreenSpaceOraclePass::paramSpec() {
    ParamSpec<ScreenSpaceOracleParams> s;
    s.add("rays", &Params::rays,
          "rays per pixel for each lobe (diffuse: cosine; specular: the pixel's GGX lobe, VNDF "
          "sampled); the noise falls as 1/√rays")
        .range(1, 65536);
    s.add("thickness", &Params::thickness,
          "cm: a sample at most this far behind a pixel's surface hits it; further behind, the ray "
          "passes behind the object")
        .range(0.0, 1e9);
    s.add("aoRadius", &Params::aoRadius,
          "metres: aoWithinRadius counts hits closer than this (capture --truth-ao-radius)")
        .range(0.0, 1e9);
    return s;
}

PassIO ScreenSpaceOraclePass::describe() const {
    PassIO io;
    // The error breakdown's oracle rung: which output estimates which truth layer.
    io.roles.raysParam = "rays";
    io.roles.oracleFor = {{"Truth.DiffuseIndirectOneBounce", kDiffuse},
                          {"Truth.DiffuseIndirectFull", kDiffuse},
                          {"Truth.AO", kAoWithinRadius}};
    io.inputs = {
        gbuffer::depthInput("full-resolution linear depth: what the rays march against"),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit (0) and sky pixels are skipped"),
        gbuffer::baseColorInput("the specular lobe's F0 (with metallic and specular)"),
        gbuffer::metallicInput("the specular lobe's F0"),
        gbuffer::specularInput("the specular lobe's F0"),
        gbuffer::roughnessInput("the specular lobe's width"),
        {.name = kColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .captureDefault = "PrevSceneColor",
         .doc = "last frame's colour (what SSGI reads), read at the nearest pixel to where each "
                "hit pixel's surface was last frame; off last frame's screen it is 0"},
        gbuffer::velocityInput("optional per-pixel motion; camera reprojection when unbound"),
    };
    io.outputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "mean radiance of the cosine rays (irradiance/π, as ssgi.diffuse and "
                "Truth.DiffuseIndirectOneBounce); 0 on skipped pixels"},
        {.name = kSpecularOut,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "indirect specular radiance through the pixel's GGX lobe (F·D·Vis, as "
                "Truth.Specular); traced only when read"},
        {.name = kHitFraction, .channels = {"Y"}, .doc = "fraction of the cosine rays that hit"},
        {.name = kAo, .channels = {"Y"}, .doc = "1 − hitFraction: occluders at any distance on screen"},
        {.name = kAoWithinRadius,
         .channels = {"Y"},
         .doc = "1 − the fraction of cosine rays that hit within aoRadius (as Truth.AO)"},
    };
    io.needsCamera = true;
    io.workUnit = "marchSteps";
    return io;
}

void ScreenSpaceOraclePass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const CameraView& cam = frame.camera.current;
    // Without last frame's camera (and no motion vectors) the scene is taken as still.
    const CameraView& prev = frame.camera.previous ? *frame.camera.previous : cam;
    const int W = frame.extent.width, H = frame.extent.height;
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Image& normal = ctx.input(gbuffer::kNormal)->image();
    const Plane& model = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Image& baseColor = ctx.input(gbuffer::kBaseColor)->image();
    const Plane& metallic = ctx.input(gbuffer::kMetallic)->image().plane(0);
    const Plane& specular = ctx.input(gbuffer::kSpecular)->image().plane(0);
    const Plane& roughness = ctx.input(gbuffer::kRoughness)->image().plane(0);
    const Image& color = ctx.input(kColor)->image();
    const Texture* velocity = ctx.input(gbuffer::kVelocity);
    FP_CHECK(color.width() == W && color.height() == H,
             "screen_space_oracle: color is {}×{}, the frame {}×{}: it reads last frame's colour at "
             "full resolution", color.width(), color.height(), W, H);

    const double cm = frame.camera.sceneUnitsPerMeter / 100.0;
    const ScreenSpace screen(cam, depth, normal, float(mParams.thickness * cm));
    const float aoRadius = float(mParams.aoRadius * frame.camera.sceneUnitsPerMeter);

    // Last frame's colour where each pixel's surface was: what a ray that hits the pixel gathers.
    std::vector<Vec3f> hitColor(std::size_t(W) * H);
    forEachTile(W, H, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const double d = depth.at(x, y);
                if (!std::isfinite(d)) continue;
                const PreviousPixel p = reprojectPixelAtDepth(cam, x, y, d, velocity, prev);
                if (!p.onScreen({W, H})) continue;
                const int u = int(p.u), v = int(p.v);
                hitColor[std::size_t(y) * W + x] = {sanitized(color.plane(0).at(u, v)),
                                                    sanitized(color.plane(1).at(u, v)),
                                                    sanitized(color.plane(2).at(u, v))};
            }
    });

    // Only what is read is allocated and traced: the cosine rays feed diffuse, hitFraction and the
    // two AOs; the GGX rays feed specular.
    const HostPorts ports{ctx};
    auto plane = [&](const char* port, int c = 0) -> Plane* {
        Texture* t = ports.outputIfRequested(port, {frame.extent});
        return t ? &t->image().plane(c) : nullptr;
    };
    Texture* diffuseOut = ports.outputIfRequested(kDiffuse, {frame.extent});
    Texture* specularOut = ports.outputIfRequested(kSpecularOut, {frame.extent});
    Plane* hitOut = plane(kHitFraction);
    Plane* aoOut = plane(kAo);
    Plane* aoRadiusOut = plane(kAoWithinRadius);
    const bool wantDiffuse = diffuseOut || hitOut || aoOut || aoRadiusOut;
    const int rays = mParams.rays;
    const float inverseRays = 1.0f / float(rays);
    const Vec3f right(cam.right), up(cam.up), forward(cam.forward);
    auto toView = [&](const Vec3f& L) { return Vec3f{dot(L, right), dot(L, up), dot(L, forward)}; };

    // One lobe's rays from pixel (x, y): Σ weight/pdf × the colour at each hit (the cosine lobe's
    // weight/pdf is exactly 1), the hits, and those closer than aoRadius.
    struct LobeSum {
        Vec3f radiance;
        int hits = 0, near = 0;
    };
    auto gather = [&](const ScatterLobe& lobe, int x, int y, const Vec3f& p0, Rng& rng,
                      uint64_t& rayCount, uint64_t& steps) {
        LobeSum sum;
        for (int r = 0; r < rays && lobe.active(); ++r) {
            const float c = rng.nextFloat(), u = rng.nextFloat(), v = rng.nextFloat();
            Vec3f L;
            if (!lobe.sample(c, u, v, L)) continue;
            const LobeValue lv = lobe.evaluate(L);
            if (!(lv.pdf > 0.0f)) continue;
            ++rayCount;
            const March m = screen.march(x, y, p0, toView(L), steps);
            if (m.pixel < 0) continue;
            sum.radiance += lv.weight * (1.0f / lv.pdf) * hitColor[std::size_t(m.pixel)];
            ++sum.hits;
            sum.near += m.distance < aoRadius ? 1 : 0;
        }
        return sum;
    };

    forEachTile(W, H, [&](const Tile& t) {
        uint64_t traced = 0, skipped = 0, rayCount = 0, steps = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const float d = depth.at(x, y);
                if (!isLitSurface(d, model.at(x, y))) {
                    if (aoOut) aoOut->at(x, y) = 1.0f;
                    if (aoRadiusOut) aoRadiusOut->at(x, y) = 1.0f;
                    ++skipped;
                    continue;
                }
                ++traced;
                const Vec3f p0 = screen.position(x, y, d);
                // The surface as the truth tracer's lobes see it (world axes, camera-relative).
                SurfacePoint s;
                s.position = Vec3f(cam.translatedFromPixel(x, y, d));
                s.normal = s.geometricNormal = normalize(gbuffer::worldNormalAt(normal, x, y));
                s.toViewer = normalize(-s.position);
                s.brdf = SurfaceBRDF::fromMaterial(
                    {baseColor.plane(0).at(x, y), baseColor.plane(1).at(x, y), baseColor.plane(2).at(x, y)},
                    metallic.at(x, y), specular.at(x, y), roughness.at(x, y));
                Rng rng(frame.number, x, y, kSeedOracle);
                if (wantDiffuse) {
                    const LobeSum g = gather(ScatterLobe(ScatterLobe::Kind::Cosine, s), x, y, p0, rng,
                                             rayCount, steps);
                    if (diffuseOut)
                        for (int c = 0; c < 3; ++c)
                            diffuseOut->image().plane(c).at(x, y) = g.radiance[c] * inverseRays;
                    if (hitOut) hitOut->at(x, y) = float(g.hits) * inverseRays;
                    if (aoOut) aoOut->at(x, y) = 1.0f - float(g.hits) * inverseRays;
                    if (aoRadiusOut) aoRadiusOut->at(x, y) = 1.0f - float(g.near) * inverseRays;
                }
                if (specularOut) {
                    const LobeSum g = gather(ScatterLobe(ScatterLobe::Kind::Specular, s), x, y, p0,
                                             rng, rayCount, steps);
                    for (int c = 0; c < 3; ++c)
                        specularOut->image().plane(c).at(x, y) = g.radiance[c] / float(rays);
                }
            }
        ctx.addWork("pixels", traced);
        ctx.addWork("skippedPixels", skipped);
        ctx.addWork("rays", rayCount);
        ctx.addWork("marchSteps", steps);
    });
}

}  // namespace fp
