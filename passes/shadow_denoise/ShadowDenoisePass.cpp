#include "passes/shadow_denoise/ShadowDenoisePass.h"

#include "passes/core/RayScene.h"
#include "passes/core/ShadingModel.h"
#include "passes/core/Tiles.h"
#include "passes/core/UnrealRandom.h"
#include "passes/lighting/LightAttenuation.h"
#include "passes/lighting/NamedLight.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace fp {

namespace {

constexpr const char* kShadow = "shadow";
constexpr const char* kTransmission = "transmission";
constexpr const char* kHitDistance = "hitDistance";
constexpr const char* kDepth = "depth";
constexpr const char* kNormal = "normal";
constexpr const char* kShadingModel = "shadingModel";
constexpr const char* kLightAttenuation = "lightAttenuation";

constexpr float kGoldenAngle = 2.39996323f;
// Plane-distance tolerance in pixel footprints (the SSGI preset's 2√2 × 3, reference §6.2).
constexpr float kPlaneTolerance = 2.0f * 1.41421356f * 3.0f;

// World-space half-width of the penumbra behind an occluder `hit` away (reference §6.3).
float penumbraRadius(const Light& light, float hit, float lightDistance) {
    switch (light.type) {
        case LightType::Directional:
            return std::tan(0.5f * light.sourceAngleDegrees * kPiF / 180.0f) * hit;
        case LightType::Rect: {
            // A rect light as the disk of the same area.
            const float area = 4.0f * float(length(cross(light.halfU, light.halfV)));
            return std::sqrt(area / kPiF) * hit /
                   std::max(lightDistance - hit, 1e-6f * lightDistance);
        }
        default:
            return light.radius * hit / std::max(lightDistance - hit, 1e-6f * lightDistance);
    }
}

}  // namespace

ParamSpec<ShadowDenoiseParams> ShadowDenoisePass::paramSpec() {
    ParamSpec<ShadowDenoiseParams> s;
    s.add("denoiser", &Params::denoiser,
          "0 off (raw shadow), 1 or 2 on (2, a third-party denoiser in Unreal, runs framepass's) "
          "(reference §6.3)")
        .range(0, 2)
        .cvar("r.Shadow.Denoiser");
    s.add("light", &Params::light, "name of the light (\"\" = the scene's only light)");
    s.add("reconstructionSamples", &Params::reconstructionSamples, "taps of each filtering pass")
        .range(1, 64)
        .cvar("r.Shadow.Denoiser.ReconstructionSamples");
    s.add("preConvolution", &Params::preConvolution, "filtering passes before the reconstruction")
        .range(0, 4)
        .cvar("r.Shadow.Denoiser.PreConvolution");
    s.add("maxRadius", &Params::maxRadius, "largest blur radius, pixels").range(0.0, 256.0);
    return s;
}

PassIO ShadowDenoisePass::describe() const {
    PassIO io;
    io.inputs = {
        {.name = kShadow, .channels = {"Y"}, .doc = "raw visibility"},
        {.name = kTransmission, .channels = {"Y"}, .doc = "raw subsurface term"},
        {.name = kHitDistance, .channels = {"Y"}, .doc = "closest occluder distance (−1 = none)"},
        {.name = kDepth,
         .channels = {"Z"},
         .captureDefault = "SceneDepth",
         .doc = "linear view depth"},
        {.name = kNormal,
         .channels = {"X", "Y", "Z"},
         .captureDefault = "WorldNormal",
         .doc = "world normal"},
        {.name = kShadingModel,
         .channels = {"Y"},
         .captureDefault = "ShadingModel",
         .doc = "unlit and sky pixels are neither filtered nor used"},
    };
    io.outputs = {
        {.name = kShadow, .channels = {"Y"}, .doc = "filtered visibility"},
        {.name = kTransmission, .channels = {"Y"}, .doc = "filtered subsurface term"},
        {.name = kLightAttenuation,
         .channels = {"R", "G", "B", "A"},
         .doc = "Unreal's light-attenuation encoding of the filtered result (reference §9.5)"},
    };
    io.needsCamera = true;
    io.needsScene = true;  // the light's size and position
    return io;
}

void ShadowDenoisePass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const CameraView& cam = frame.camera.current;
    const RayScene& rs = ctx.scene();
    const Light& light = namedLight(rs.scene(), mParams.light);
    const Extent size = frame.extent;
    const int W = size.width, H = size.height;
    const Plane& depth = ctx.input(kDepth)->image().plane(0);
    const Image& normal = ctx.input(kNormal)->image();
    const Plane& models = ctx.input(kShadingModel)->image().plane(0);
    const Plane& hits = ctx.input(kHitDistance)->image().plane(0);
    // Planes share their pixels when copied: the filter works on copies of its own.
    auto copyOf = [&](const Image& from) {
        Image to(W, H, from.channels());
        for (int c = 0; c < from.channelCount(); ++c)
            for (int y = 0; y < H; ++y)
                std::memcpy(to.plane(c).row(y), from.plane(c).row(y), sizeof(float) * W);
        return to;
    };
    Image raw(W, H, {"S", "T"});  // shadow, transmission
    raw.plane(0) = ctx.input(kShadow)->image().plane(0);
    raw.plane(1) = ctx.input(kTransmission)->image().plane(0);
    Image signal = copyOf(raw);

    auto lit = [&](int x, int y) { return isLitSurface(depth.at(x, y), models.at(x, y)); };
    // Camera-relative positions, rebuilt once: every filtering pass reads them at each tap.
    Image positions(W, H, {"X", "Y", "Z"});
    if (mParams.denoiser > 0)
        forEachTile(W, H, [&](const Tile& t) {
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) {
                    if (!lit(x, y))
                        continue;
                    const Vec3f p(cam.translatedFromPixel(x, y, depth.at(x, y)));
                    for (int c = 0; c < 3; ++c)
                        positions.plane(c).at(x, y) = p[c];
                }
        });
    auto positionOf = [&](int x, int y) {
        return Vec3f{positions.plane(0).at(x, y), positions.plane(1).at(x, y),
                     positions.plane(2).at(x, y)};
    };
    auto normalOf = [&](int x, int y) {
        return Vec3f{normal.plane(0).at(x, y), normal.plane(1).at(x, y), normal.plane(2).at(x, y)};
    };
    const int taps = mParams.reconstructionSamples;
    // Golden-angle spiral of `taps` points in the unit disk, rotated per pixel (IGN) and pass.
    auto tapOffset = [&](int k, float rotation, float radius, int& dx, int& dy) {
        const float r = radius * std::sqrt((float(k) + 0.5f) / float(taps));
        const float a = float(k) * kGoldenAngle + rotation;
        dx = int(std::lround(r * std::cos(a)));
        dy = int(std::lround(r * std::sin(a)));
    };

    // Blur radius per pixel, in pixels: from its own occluder, else the closest one around it
    // (a lit pixel next to a shadow is in that shadow's penumbra).
    // Pixels without a radius of at least half a pixel are left as they are (and counted).
    Plane radius(W, H);
    if (mParams.denoiser > 0) {
        const Vec3f lightPos(light.position - cam.position);
        forEachTile(W, H, [&](const Tile& t) {
            uint64_t filtered = 0;
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) {
                    if (!lit(x, y))
                        continue;
                    float hit = hits.at(x, y);
                    const float rotation =
                        2.0f * kPiF * ue::interleavedGradientNoise(float(x), float(y), 0);
                    for (int k = 0; k < taps && hit < 0.0f; ++k) {
                        int dx, dy;
                        tapOffset(k, rotation, mParams.maxRadius, dx, dy);
                        const int sx = std::clamp(x + dx, 0, W - 1),
                                  sy = std::clamp(y + dy, 0, H - 1);
                        const float h = hits.at(sx, sy);
                        if (h >= 0.0f && lit(sx, sy))
                            hit = h;
                    }
                    if (hit < 0.0f)
                        continue;
                    const Vec3f p = positionOf(x, y);
                    const float world = penumbraRadius(light, hit, length(lightPos - p));
                    const float footprint = 2.0f * float(cam.pixelRadiusAtDepth(depth.at(x, y)));
                    radius.at(x, y) = std::min(world / footprint, mParams.maxRadius);
                    filtered += radius.at(x, y) >= 0.5f;
                }
            ctx.addWork("pixels", filtered);
            ctx.addWork("skippedPixels", uint64_t(t.x1 - t.x0) * (t.y1 - t.y0) - filtered);
        });
        for (int pass = 0; pass <= mParams.preConvolution; ++pass) {
            Image out = copyOf(signal);
            forEachTile(W, H, [&](const Tile& t) {
                for (int y = t.y0; y < t.y1; ++y)
                    for (int x = t.x0; x < t.x1; ++x) {
                        const float r = radius.at(x, y);
                        if (!lit(x, y) || r < 0.5f)
                            continue;  // no penumbra: nothing to blur
                        const Vec3f p = positionOf(x, y), n = normalOf(x, y);
                        const float tolerance =
                            kPlaneTolerance * float(cam.pixelRadiusAtDepth(depth.at(x, y)));
                        float sumS = signal.plane(0).at(x, y), sumT = signal.plane(1).at(x, y);
                        float sumW = 1.0f;
                        const float rotation =
                            2.0f * kPiF *
                            ue::interleavedGradientNoise(float(x), float(y), uint32_t(pass + 1));
                        for (int k = 0; k < taps; ++k) {
                            int dx, dy;
                            tapOffset(k, rotation, r, dx, dy);
                            const int sx = x + dx, sy = y + dy;
                            if (sx < 0 || sy < 0 || sx >= W || sy >= H || !lit(sx, sy))
                                continue;
                            // Bilateral (reference §6.3): the receiver's plane and normal⁴.
                            const float planeW = std::clamp(
                                1.0f - std::fabs(dot(n, positionOf(sx, sy) - p)) / tolerance, 0.0f,
                                1.0f);
                            const float nw = std::max(dot(n, normalOf(sx, sy)), 0.0f);
                            const float w = planeW * (nw * nw) * (nw * nw);
                            sumS += w * signal.plane(0).at(sx, sy);
                            sumT += w * signal.plane(1).at(sx, sy);
                            sumW += w;
                        }
                        out.plane(0).at(x, y) = sumS / sumW;
                        out.plane(1).at(x, y) = sumT / sumW;
                    }
            });
            signal = std::move(out);
        }
    } else {
        ctx.addWork("pixels", 0);
        ctx.addWork("skippedPixels", uint64_t(W) * H);
    }

    Plane& shadowOut = ctx.output(kShadow, {size}).image().plane(0);
    Plane& transmissionOut = ctx.output(kTransmission, {size}).image().plane(0);
    Image& attenuation = ctx.output(kLightAttenuation, {size}).image();
    forEachTile(W, H, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const float s = signal.plane(0).at(x, y), tr = signal.plane(1).at(x, y);
                shadowOut.at(x, y) = s;
                transmissionOut.at(x, y) = tr;
                LightAttenuation::fromShadow(light.type, s, tr).store(attenuation, x, y);
            }
    });
}

}  // namespace fp
