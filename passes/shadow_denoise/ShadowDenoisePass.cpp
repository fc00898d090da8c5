#include "passes/shadow_denoise/ShadowDenoisePass.h"

#include "screenspace/Bilateral.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Surface.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/Tiles.h"
#include "foundation/UnrealRandom.h"
#include "shading/LightAttenuation.h"
#include "shading/NamedLight.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kShadow = "shadow";
constexpr const char* kTransmission = "transmission";
constexpr const char* kHitDistance = "hitDistance";
constexpr const char* kLightAttenuation = "lightAttenuation";

constexpr float kGoldenAngle = 2.39996323f;
// Plane-distance tolerance in pixel footprints (the SSGI preset's 2√2 × 3, algorithms §6.2).
constexpr float kPlaneTolerance = 2.0f * 1.41421356f * 3.0f;

// World-space half-width of the penumbra behind an occluder `hit` away (algorithms §6.3).
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

// The radii of a golden-angle spiral of `taps` points in the unit disk: √((k + ½)/taps).
struct Spiral {
    int taps;
    std::array<float, 64> unitRadius;  // reconstructionSamples ≤ 64

    explicit Spiral(int tapCount) : taps(tapCount), unitRadius{} {
        FP_CHECK(taps >= 0 && taps <= int(unitRadius.size()), "{} taps: at most {}", taps,
                 unitRadius.size());
        for (int k = 0; k < taps; ++k)
            unitRadius[k] = std::sqrt((float(k) + 0.5f) / float(taps));
    }

    // Tap k scaled to `radius` pixels and rotated by `rotation` (per pixel from IGN, and per
    // pass), so the few taps of each pass cover the disk evenly and neighbouring pixels sample it
    // differently.
    void tapOffset(int k, float rotation, float radius, int& dx, int& dy) const {
        const float r = radius * unitRadius[k];
        const float a = float(k) * kGoldenAngle + rotation;
        if (!(std::fabs(r) < 1e6f)) {  // a NaN/inf radius: the centre tap
            dx = dy = 0;
            return;
        }
        dx = roundHalfAwayToInt(r * std::cos(a));
        dy = roundHalfAwayToInt(r * std::sin(a));
    }
};

// How many pixels hold an occluder distance (a valid surface with a hit) in any rectangle: a
// summed-area table, so a pixel whose every tap would land where no occluder is skips its taps.
class OccluderCounts {
public:
    OccluderCounts(const SurfaceGrid& surfaces, const Plane& hits)
        : mWidth(hits.width()), mHeight(hits.height()),
          mSum(std::size_t(mWidth + 1) * (mHeight + 1), 0u) {
        for (int y = 0; y < mHeight; ++y) {
            uint32_t row = 0;
            for (int x = 0; x < mWidth; ++x) {
                row += hits.at(x, y) >= 0.0f && surfaces.at(x, y).valid;
                at(x + 1, y + 1) = at(x + 1, y) + row;
            }
        }
    }

    /// Occluder pixels in the square of half-width `reach` around (x, y), clipped to the image.
    uint32_t around(int x, int y, int reach) const {
        const int x0 = std::max(x - reach, 0), x1 = std::min(x + reach + 1, mWidth);
        const int y0 = std::max(y - reach, 0), y1 = std::min(y + reach + 1, mHeight);
        return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
    }

private:
    uint32_t& at(int x, int y) { return mSum[std::size_t(y) * (mWidth + 1) + x]; }
    uint32_t at(int x, int y) const { return mSum[std::size_t(y) * (mWidth + 1) + x]; }

    int mWidth, mHeight;
    std::vector<uint32_t> mSum;
};

// What the blur radius of a pixel depends on (algorithms §6.3).
struct RadiusInputs {
    const Light& light;
    Vec3f lightPos;  // camera-relative
    const SurfaceGrid& surfaces;
    const Plane& hits;
    const OccluderCounts& occluders;
    const Spiral& spiral;
    float maxRadius;  // pixels
};

// The blur radius of one lit pixel, in pixels: the penumbra width behind its own occluder, else
// behind the closest occluder around it (a lit pixel next to a shadow is in that shadow's
// penumbra); 0 where no occluder is found.
float blurRadius(const RadiusInputs& in, int x, int y) {
    const int W = in.hits.width(), H = in.hits.height();
    float hit = in.hits.at(x, y);
    // A tap lands at most round(maxRadius) pixels away (clamped into the image): with no occluder
    // in that square the search below finds none, so it is not run.
    const int reach = int(std::ceil(in.maxRadius)) + 1;
    if (hit < 0.0f && in.occluders.around(x, y, reach) == 0)
        return 0.0f;
    const float rotation = 2.0f * kPiF * ue::interleavedGradientNoise(float(x), float(y), 0);
    for (int k = 0; k < in.spiral.taps && hit < 0.0f; ++k) {
        int dx, dy;
        in.spiral.tapOffset(k, rotation, in.maxRadius, dx, dy);
        const int sx = std::clamp(x + dx, 0, W - 1), sy = std::clamp(y + dy, 0, H - 1);
        const float h = in.hits.at(sx, sy);
        if (h >= 0.0f && in.surfaces.at(sx, sy).valid)
            hit = h;
    }
    if (hit < 0.0f)
        return 0.0f;
    const Surface& s = in.surfaces.at(x, y);
    const float world = penumbraRadius(in.light, hit, length(in.lightPos - s.position));
    const float footprint = 2.0f * s.radius;
    return std::min(world / footprint, in.maxRadius);
}

// One filtering pass at one pixel with radius r ≥ ½: the centre and `taps` spiral taps, each
// weighted by the receiver's plane and normal⁴ (algorithms §6.3); S and T are filtered together.
void filterPixel(const SurfaceGrid& surfaces,
                 const Image& signal,
                 const Spiral& spiral,
                 int pass,
                 int x,
                 int y,
                 float r,
                 Image& out) {
    const int W = signal.width(), H = signal.height();
    const Surface& ref = surfaces.at(x, y);
    const float tolerance = kPlaneTolerance * ref.radius;
    float sumS = signal.plane(0).at(x, y), sumT = signal.plane(1).at(x, y);
    float sumW = 1.0f;
    const float rotation =
        2.0f * kPiF * ue::interleavedGradientNoise(float(x), float(y), uint32_t(pass + 1));
    for (int k = 0; k < spiral.taps; ++k) {
        int dx, dy;
        spiral.tapOffset(k, rotation, r, dx, dy);
        const int sx = x + dx, sy = y + dy;
        if (sx < 0 || sy < 0 || sx >= W || sy >= H || !surfaces.at(sx, sy).valid)
            continue;
        const float w = bilateralWeight(ref, surfaces.at(sx, sy), tolerance);
        sumS += w * signal.plane(0).at(sx, sy);
        sumT += w * signal.plane(1).at(sx, sy);
        sumW += w;
    }
    out.plane(0).at(x, y) = sumS / sumW;
    out.plane(1).at(x, y) = sumT / sumW;
}

}  // namespace

ParamSpec<ShadowDenoiseParams> ShadowDenoisePass::paramSpec() {
    ParamSpec<ShadowDenoiseParams> s;
    s.add("denoiser", &Params::denoiser,
          "0 off (raw shadow), 1 or 2 on (2, a third-party denoiser in Unreal, runs framepass's) "
          "(algorithms §6.3)")
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
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit and sky pixels are neither filtered nor used"),
    };
    io.outputs = {
        {.name = kShadow, .channels = {"Y"}, .doc = "filtered visibility"},
        {.name = kTransmission, .channels = {"Y"}, .doc = "filtered subsurface term"},
        {.name = kLightAttenuation,
         .channels = {"R", "G", "B", "A"},
         .doc = "Unreal's light-attenuation encoding of the filtered result (algorithms §9.5)"},
    };
    io.needsCamera = true;
    io.needsLights = true;  // the light's size and position
    return io;
}

Plane ShadowDenoisePass::blurRadii(PassContext& ctx,
                                   const Light& light,
                                   const SurfaceGrid& surfaces) const {
    const CameraView& cam = ctx.frame().camera.current;
    const Plane& hits = ctx.input(kHitDistance)->image().plane(0);
    const int W = hits.width(), H = hits.height();
    const OccluderCounts occluders(surfaces, hits);
    const Spiral spiral(mParams.reconstructionSamples);
    const RadiusInputs in{light,     Vec3f(light.position - cam.position), surfaces, hits,
                          occluders, spiral,                               mParams.maxRadius};
    // Pixels without a radius of at least half a pixel are left as they are (and counted).
    Plane radius(W, H);
    forEachTile(W, H, [&](const Tile& t) {
        uint64_t filtered = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (!surfaces.at(x, y).valid)
                    continue;
                radius.at(x, y) = blurRadius(in, x, y);
                filtered += radius.at(x, y) >= 0.5f;
            }
        ctx.addWork("pixels", filtered);
        ctx.addWork("skippedPixels", uint64_t(t.x1 - t.x0) * (t.y1 - t.y0) - filtered);
    });
    return radius;
}

Image ShadowDenoisePass::filter(const SurfaceGrid& surfaces,
                                const Plane& radius,
                                Image signal) const {
    const Spiral spiral(mParams.reconstructionSamples);
    for (int pass = 0; pass <= mParams.preConvolution; ++pass) {
        Image out(signal.width(), signal.height(), signal.channels());
        forEachTile(signal.width(), signal.height(), [&](const Tile& t) {
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) {
                    const float r = radius.at(x, y);
                    if (!surfaces.at(x, y).valid || r < 0.5f) {  // no penumbra: nothing to blur
                        out.plane(0).at(x, y) = signal.plane(0).at(x, y);
                        out.plane(1).at(x, y) = signal.plane(1).at(x, y);
                    } else {
                        filterPixel(surfaces, signal, spiral, pass, x, y, r, out);
                    }
                }
        });
        signal = std::move(out);
    }
    return signal;
}

void ShadowDenoisePass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const CameraView& cam = frame.camera.current;
    const Light& light = namedLight(ctx.lights(), mParams.light);
    const Extent size = frame.extent;
    const int W = size.width, H = size.height;
    Image raw(W, H, {"S", "T"});  // shadow, transmission
    raw.plane(0) = ctx.input(kShadow)->image().plane(0);
    raw.plane(1) = ctx.input(kTransmission)->image().plane(0);
    Image signal;
    if (mParams.denoiser > 0) {
        const SurfaceGrid surfaces(
            cam,
            {ctx.input(gbuffer::kDepth)->image().plane(0), ctx.input(gbuffer::kNormal)->image(),
             ctx.input(gbuffer::kShadingModel)->image().plane(0)},
            size, 1, NormalRead::AsStored);
        signal = filter(surfaces, blurRadii(ctx, light, surfaces), raw);
    } else {
        signal = raw;
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
