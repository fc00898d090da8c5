#pragma once
// The shadow denoiser's per-pixel work (algorithms §6.3), written once for both backends:
// ShadowDenoisePass::execute runs it with CpuPixels, ShadowDenoisePass.cu with CudaPixels. Sweeps:
// the receivers' surfaces; a summed-area table of where occluders are (rows, then columns: integer
// sums, the same on any order); each pixel's blur radius from its penumbra; the filtering passes;
// the outputs with their light-attenuation encoding.
#include "foundation/Camera.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/Scene.h"
#include "foundation/SinCos.h"
#include "foundation/UnrealRandom.h"
#include "framework/Pass.h"
#include "screenspace/Bilateral.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Surface.h"
#include "shading/LightAttenuation.h"

#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace fp::shadow_denoise {

inline constexpr const char* kShadow = "shadow";
inline constexpr const char* kTransmission = "transmission";
inline constexpr const char* kHitDistance = "hitDistance";
inline constexpr const char* kLightAttenuation = "lightAttenuation";

constexpr float kGoldenAngle = 2.39996323f;
// Plane-distance tolerance in pixel footprints (the SSGI preset's 2√2 × 3, algorithms §6.2).
constexpr float kPlaneTolerance = 2.0f * 1.41421356f * 3.0f;
constexpr int kMaxTaps = 64;

/// What the penumbra's width depends on (algorithms §6.3): behind an occluder `hit` away it is
/// tan(½·angle)·hit for a directional light, size·hit/(D − hit) for a local one of that radius
/// (a rect light as the disk of the same area), D the receiver's distance to the light.
struct Penumbra {
    bool directional = false;
    float size = 0;  //!< tan(½·angle) (directional) or the light's radius
    Vec3f lightPos;  //!< camera-relative

    static Penumbra of(const Light& light, const Vec3d& eye) {
        Penumbra p;
        p.lightPos = Vec3f(light.position - eye);
        switch (light.type) {
            case LightType::Directional:
                p.directional = true;
                p.size = std::tan(0.5f * light.sourceAngleDegrees * kPiF / 180.0f);
                break;
            case LightType::Rect:
                p.size = std::sqrt(4.0f * float(length(cross(light.halfU, light.halfV))) / kPiF);
                break;
            default:
                p.size = light.radius;
        }
        return p;
    }
    /// The world-space half-width of the penumbra.
    FP_HD float radius(float hit, float lightDistance) const {
        if (directional) return size * hit;
        const float gap = lightDistance - hit, floor = 1e-6f * lightDistance;
        return size * hit / (gap < floor ? floor : gap);
    }
};

/// The radii of a golden-angle spiral of `taps` points in the unit disk: √((k + ½)/taps).
struct Spiral {
    int taps = 0;
    float unitRadius[kMaxTaps] = {};

    static Spiral of(int taps) {
        FP_CHECK(taps >= 0 && taps <= kMaxTaps, "{} taps: at most {}", taps, kMaxTaps);
        Spiral s;
        s.taps = taps;
        for (int k = 0; k < taps; ++k) s.unitRadius[k] = std::sqrt((float(k) + 0.5f) / float(taps));
        return s;
    }

    /// Tap k scaled to `radius` pixels and rotated by `rotation` (per pixel from IGN, and per
    /// pass), so the few taps of each pass cover the disk evenly and neighbouring pixels sample it
    /// differently. The angle goes through SinCos.h: the same offsets on both backends.
    FP_HD void tapOffset(int k, float rotation, float radius, int& dx, int& dy) const {
        const float r = radius * unitRadius[k];
        const float a = float(k) * kGoldenAngle + rotation;
        if (!(std::fabs(r) < 1e6f)) {  // a NaN/inf radius: the centre tap
            dx = dy = 0;
            return;
        }
        float s, c;
        sinCos(a, s, c);
        dx = roundHalfAwayToInt(r * c);
        dy = roundHalfAwayToInt(r * s);
    }
};

/// Occluder pixels (a valid surface with a hit) in any rectangle: a summed-area table of
/// (W + 1) × (H + 1) counts, so a pixel whose every tap would land where no occluder is skips its
/// taps.
struct OccluderCounts {
    uint32_t* sum = nullptr;
    int width = 0, height = 0;

    FP_HD uint32_t& at(int x, int y) const { return sum[y * (width + 1) + x]; }
    /// Occluder pixels in the square of half-width `reach` around (x, y), clipped to the image.
    FP_HD uint32_t around(int x, int y, int reach) const {
        const int x0 = x - reach > 0 ? x - reach : 0, x1 = x + reach + 1 < width ? x + reach + 1 : width;
        const int y0 = y - reach > 0 ? y - reach : 0, y1 = y + reach + 1 < height ? y + reach + 1 : height;
        return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
    }
};

/// Everything the sweeps read and write.
struct Frame {
    CameraView cam;
    SurfaceInputsView gbuffer;
    SurfaceGridView surfaces;
    PlaneView hits;
    OccluderCounts occluders;
    Spiral spiral;
    Penumbra penumbra;
    float maxRadius;
    PlaneSpan radius;
    int width, height;
};

/// Row y of the occluder table: its running count along the row (then the column sweep adds the
/// rows above). Row 0 and column 0 are zero.
FP_HD inline void occluderRow(const Frame& f, int y) {
    const OccluderCounts& o = f.occluders;
    if (y == 0)
        for (int x = 0; x <= f.width; ++x) o.at(x, 0) = 0;
    o.at(0, y + 1) = 0;
    uint32_t row = 0;
    for (int x = 0; x < f.width; ++x) {
        row += f.hits.at(x, y) >= 0.0f && f.surfaces.at(x, y).valid;
        o.at(x + 1, y + 1) = row;
    }
}

/// Column x of the occluder table: the rows' running counts summed downwards.
FP_HD inline void occluderColumn(const Frame& f, int x) {
    for (int y = 1; y <= f.height; ++y) f.occluders.at(x, y) += f.occluders.at(x, y - 1);
}

/// The occluder table: a sweep along each row, then down each column. The counts are integers, so
/// any order of additions gives the same table: the GPU builds it its own way (below).
template <class Pixels>
void buildOccluderTable(const Frame& f, const Pixels& pixels) {
    pixels.template forEach<0>(
        1, f.height, [=] FP_HD(int, int y, WorkCounts<0>&) { occluderRow(f, y); },
        "shadow_denoise rows");
    pixels.template forEach<0>(
        f.width + 1, 1, [=] FP_HD(int x, int, WorkCounts<0>&) { occluderColumn(f, x); },
        "shadow_denoise columns");
}
/// The GPU's (ShadowDenoisePass.cu): a warp scans each row 32 pixels at a time, then a block of
/// 32 × 32 threads sums 32 columns in 32 segments, reading and writing whole rows at once; one
/// thread a row, as above, would read a row's pixels one by one, 1,920 dependent steps apart.
void buildOccluderTable(const Frame& f, const CudaPixels& pixels);

/// The blur radius of one valid pixel, in pixels: the penumbra width behind its own occluder,
/// else behind the closest occluder around it (a lit pixel next to a shadow is in that shadow's
/// penumbra); 0 where no occluder is found.
FP_HD inline float blurRadius(const Frame& f, int x, int y) {
    float hit = f.hits.at(x, y);
    // A tap lands at most round(maxRadius) pixels away (clamped into the image): with no occluder
    // in that square the search below finds none, so it is not run.
    const int reach = int(std::ceil(f.maxRadius)) + 1;
    if (hit < 0.0f && f.occluders.around(x, y, reach) == 0) return 0.0f;
    const float rotation = 2.0f * kPiF * ue::interleavedGradientNoise(float(x), float(y), 0);
    for (int k = 0; k < f.spiral.taps && hit < 0.0f; ++k) {
        int dx, dy;
        f.spiral.tapOffset(k, rotation, f.maxRadius, dx, dy);
        const int sx = truncToInt(x + dx, 0, f.width - 1), sy = truncToInt(y + dy, 0, f.height - 1);
        const float h = f.hits.at(sx, sy);
        if (h >= 0.0f && f.surfaces.at(sx, sy).valid) hit = h;
    }
    if (hit < 0.0f) return 0.0f;
    const Surface& s = f.surfaces.at(x, y);
    const float world = f.penumbra.radius(hit, length(f.penumbra.lightPos - s.position));
    const float footprint = 2.0f * s.radius;
    const float r = world / footprint;
    return f.maxRadius < r ? f.maxRadius : r;  // std::min
}

/// One filtering pass at one pixel (algorithms §6.3): with a radius r ≥ ½ the centre and the
/// spiral's taps, each weighted by the receiver's plane and normal⁴, S and T filtered together;
/// otherwise (no penumbra, or no surface) the pixel as it is.
FP_HD inline void filterPixel(const Frame& f, const PlaneView (&in)[2], const PlaneSpan (&out)[2], int pass,
                              int x, int y) {
    const float r = f.radius.at(x, y);
    const Surface& ref = f.surfaces.at(x, y);
    if (!ref.valid || r < 0.5f) {
        out[0].at(x, y) = in[0].at(x, y);
        out[1].at(x, y) = in[1].at(x, y);
        return;
    }
    const float tolerance = kPlaneTolerance * ref.radius;
    float sumS = in[0].at(x, y), sumT = in[1].at(x, y);
    float sumW = 1.0f;
    const float rotation = 2.0f * kPiF * ue::interleavedGradientNoise(float(x), float(y), uint32_t(pass + 1));
    for (int k = 0; k < f.spiral.taps; ++k) {
        int dx, dy;
        f.spiral.tapOffset(k, rotation, r, dx, dy);
        const int sx = x + dx, sy = y + dy;
        if (sx < 0 || sy < 0 || sx >= f.width || sy >= f.height || !f.surfaces.at(sx, sy).valid) continue;
        const float w = bilateralWeight(ref, f.surfaces.at(sx, sy), tolerance);
        sumS += w * in[0].at(sx, sy);
        sumT += w * in[1].at(sx, sy);
        sumW += w;
    }
    out[0].at(x, y) = sumS / sumW;
    out[1].at(x, y) = sumT / sumW;
}

/// One filtering pass's images.
struct FilterIO {
    PlaneView in[2];
    PlaneSpan out[2];
};

/// The filtered signal and where it goes.
struct Outputs {
    PlaneView signal[2];
    PlaneSpan shadow, transmission, attenuation[4];
    LightType type;
};

/// The whole pass through `ports` on `pixels`, its work reported to `ctx`.
template <class Ports, class Pixels>
void run(PassContext& ctx, const Ports& ports, const Pixels& pixels, const Light& light, int denoiser,
         int reconstructionSamples, int preConvolution, float maxRadius) {
    const FrameInfo& frame = ctx.frame();
    const int W = frame.extent.width, H = frame.extent.height;
    const std::vector<Extent> extent = {frame.extent};
    PlaneView signal[2] = {viewOf(ports.input(kShadow)->image().plane(0)),
                           viewOf(ports.input(kTransmission)->image().plane(0))};
    using TextureT = std::decay_t<decltype(ports.output(kShadow, extent))>;
    TextureT ping, pong;  // the filtering passes' images, alive until the outputs are written
    if (denoiser > 0) {
        Frame f{};
        f.cam = frame.camera.current;
        f.width = W;
        f.height = H;
        const auto& normal = ports.input(gbuffer::kNormal)->image();
        f.gbuffer = {viewOf(ports.input(gbuffer::kDepth)->image().plane(0)),
                     {viewOf(normal.plane(0)), viewOf(normal.plane(1)), viewOf(normal.plane(2))},
                     viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0))};
        const auto surfaceMemory = ports.template scratchArray<Surface>(std::size_t(W) * H);
        f.surfaces = {surfaceMemory.get(), W, H, 1};
        f.hits = viewOf(ports.input(kHitDistance)->image().plane(0));
        const auto occluderMemory = ports.template scratchArray<uint32_t>(std::size_t(W + 1) * (H + 1));
        f.occluders = {occluderMemory.get(), W, H};
        f.spiral = Spiral::of(reconstructionSamples);
        f.penumbra = Penumbra::of(light, f.cam.position);
        f.maxRadius = maxRadius;
        auto radius = ports.scratch(extent, {"R"});
        f.radius = spanOf(radius.image().plane(0));

        pixels.template forEach<0>(
            W, H,
            [=] FP_HD(int x, int y, WorkCounts<0>&) {
                f.surfaces.build(f.cam, f.gbuffer, NormalRead::AsStored, x, y);
            },
            "shadow_denoise surfaces");
        buildOccluderTable(f, pixels);
        // Pixels without a radius of at least half a pixel are left as they are (and counted).
        const auto filtered = pixels.template forEach<1>(
            W, H,
            [=] FP_HD(int x, int y, WorkCounts<1>& n) {
                if (!f.surfaces.at(x, y).valid) return;
                f.radius.at(x, y) = blurRadius(f, x, y);
                n.value[0] += f.radius.at(x, y) >= 0.5f;
            },
            "shadow_denoise radii");
        ctx.addWork("pixels", filtered[0]);
        ctx.addWork("skippedPixels", uint64_t(W) * H - filtered[0]);

        ping = ports.scratch(extent, {"S", "T"});
        pong = ports.scratch(extent, {"S", "T"});
        for (int pass = 0; pass <= preConvolution; ++pass) {
            TextureT& target = pass % 2 == 0 ? ping : pong;
            FilterIO io;
            for (int c = 0; c < 2; ++c) {
                io.in[c] = signal[c];
                io.out[c] = spanOf(target.image().plane(c));
            }
            pixels.template forEach<0>(
                W, H, [=] FP_HD(int x, int y, WorkCounts<0>&) { filterPixel(f, io.in, io.out, pass, x, y); },
                "shadow_denoise filter");
            for (int c = 0; c < 2; ++c) signal[c] = viewOf(io.out[c]);
        }
    } else {
        ctx.addWork("pixels", 0);
        ctx.addWork("skippedPixels", uint64_t(W) * H);
    }

    Outputs out;
    out.signal[0] = signal[0];
    out.signal[1] = signal[1];
    out.shadow = spanOf(ports.overwrite(kShadow, extent).image().plane(0));
    out.transmission = spanOf(ports.overwrite(kTransmission, extent).image().plane(0));
    auto& attenuation = ports.overwrite(kLightAttenuation, extent);
    for (int c = 0; c < 4; ++c) out.attenuation[c] = spanOf(attenuation.image().plane(c));
    out.type = light.type;
    pixels.template forEach<0>(
        W, H,
        [=] FP_HD(int x, int y, WorkCounts<0>&) {
            const float s = out.signal[0].at(x, y), t = out.signal[1].at(x, y);
            out.shadow.at(x, y) = s;
            out.transmission.at(x, y) = t;
            const LightAttenuation la = LightAttenuation::fromShadow(out.type, s, t);
            out.attenuation[0].at(x, y) = la.r;
            out.attenuation[1].at(x, y) = la.g;
            out.attenuation[2].at(x, y) = la.b;
            out.attenuation[3].at(x, y) = la.a;
        },
        "shadow_denoise outputs");
}

/// What run() allocates on the CPU with the denoiser on: the surfaces, the occluder table and the
/// radii (freed before the filter), then the two ping-pong images.
inline PassMemory memoryOf(Extent frame, int denoiser) {
    if (denoiser <= 0) return {};
    const std::size_t pixels = std::size_t(frame.width) * std::size_t(frame.height);
    const std::size_t table = sizeof(uint32_t) * std::size_t(frame.width + 1) * std::size_t(frame.height + 1);
    return {std::max(sizeof(Surface) * pixels + table + imageBytes(frame, 1), 2 * imageBytes(frame, 2)),
            0};
}

}  // namespace fp::shadow_denoise
