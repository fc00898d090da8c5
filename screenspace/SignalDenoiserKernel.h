#pragma once
// The signal denoiser's per-pixel work (SignalDenoiser.h says what it computes), written once for
// both backends: ao_denoise, gi_denoise and reflection_denoise run ssd::run with CpuPixels from
// execute() and with CudaPixels from the .cu file beside each. Sweeps: the surfaces (and, for a
// signal traced at 1/k, the texels' own) with each pixel's kernel radius, the reconstruction, the
// pre-convolutions ping-ponging between two scratch images, the temporal accumulation, the
// history convolution — each reading only what the sweeps before it wrote.
#include "foundation/Error.h"
#include "foundation/HostDevice.h"
#include "foundation/Math.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/SinCos.h"
#include "foundation/UnrealRandom.h"
#include "framework/Pass.h"
#include "screenspace/Bilateral.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Reprojection.h"
#include "screenspace/SignalDenoiser.h"
#include "screenspace/Surface.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace fp::ssd {

namespace kernel {

constexpr float kTwoPi = 6.28318531f;
// The plane-distance tolerance of every stage: the smaller pixel world radius × 2√2 × 3, the
// diffuse preset of the SSGI denoiser (algorithms §6.2).
constexpr float kBilateralScale = 2.0f * 1.41421356f * 3.0f;
constexpr float kClampSigma = 1.25f;  // the history's neighbourhood box, as SSGI's (§6.2 step 4)
constexpr int kPreConvolutionSamples = 8;
// A pixel whose input carries no ray (hit distance < −1.5): it keeps its value and no kernel reads it.
constexpr float kNoRay = -1.0f;

enum StateChannel { kCount = kMaxSignalChannels, kViewDepth, kNX, kNY, kNZ, kStateChannels };

/// `taps` points spread evenly over the unit disc (Vogel's spiral: radius √((i + ½)/n), each
/// turned by the golden angle from the one before), computed once on the host and read by every
/// pixel (on the GPU from the kernel's parameters).
struct Disc {
    int taps = 0;
    float x[kMaxReconstructionSamples] = {}, y[kMaxReconstructionSamples] = {};

    static Disc vogel(int taps) {
        constexpr float kGoldenAngle = 2.39996323f;
        FP_CHECK(taps >= 0 && taps <= kMaxReconstructionSamples, "{} taps: at most {}", taps,
                 kMaxReconstructionSamples);
        Disc d;
        d.taps = taps;
        for (int i = 0; i < taps; ++i) {
            const float r = std::sqrt((float(i) + 0.5f) / float(taps));
            float s, c;
            sinCos(kGoldenAngle * float(i), s, c);
            d.x[i] = r * c;
            d.y[i] = r * s;
        }
        return d;
    }
};

/// The planes one sweep reads and writes: as many as the signal has channels.
struct Sources {
    PlaneView plane[kMaxSignalChannels];
};
struct Targets {
    PlaneSpan plane[kMaxSignalChannels];
};

/// Everything the sweeps share. Absent planes have null data.
struct Frame {
    Footprint footprint;
    float targetSamples;
    int channels, width, height;
    SurfaceGridView surfaces;       // the frame's
    SurfaceGridView traceSurfaces;  // the texels' (upscale > 1), each at the pixel it was traced at
    PlaneView hitDistance, roughness, depth;
    PlaneSpan radius;  // kernel radius, pixels; kNoRay where the pixel passes through
    uint32_t frameMod8;
    // A signal traced at a lower resolution (a ray-traced pass's screen percentage): each texel
    // stands for the top-left pixel of its upscale × upscale block (fullResPixel).
    int upscale, traceWidth, traceHeight;
    VelocityView velocity;  // the optional motion the history reprojects by
    CameraView camera, historyCamera;
    PlaneView history[kStateChannels];  // last frame's state; null without a usable one
    PlaneSpan state[kStateChannels];    // the next frame's; null when not accumulating

    FP_HD bool carriesSignal(int x, int y) const { return radius.at(x, y) >= 0.0f; }
    FP_HD bool hasHistory() const { return history[0].data != nullptr; }
    FP_HD Surface texelSurface(int tx, int ty) const {
        return upscale > 1 ? traceSurfaces.at(tx, ty) : surfaces.at(tx, ty);
    }
    // A texel whose ray was traced (a surface, and a hit distance above −1.5).
    FP_HD bool texelCarries(int tx, int ty) const {
        return texelSurface(tx, ty).valid && hitDistance.at(tx, ty) >= -1.5f;
    }
    FP_HD PixelCoord texelPixel(int tx, int ty) const {
        return fullResPixel(tx, ty, upscale, width, height);
    }
    // The texel a frame pixel lies in.
    FP_HD PixelCoord coveringTexel(int x, int y) const {
        return {std::min(x / upscale, traceWidth - 1), std::min(y / upscale, traceHeight - 1)};
    }
};

// The pixel under disc tap i turned and scaled by (cosine, sine) × radius about pixel (x, y).
FP_HD inline PixelCoord tapPixel(int x, int y, float cosR, float sinR, const Disc& d, int i) {
    return {int(std::floor(float(x) + 0.5f + cosR * d.x[i] - sinR * d.y[i])),
            int(std::floor(float(y) + 0.5f + sinR * d.x[i] + cosR * d.y[i]))};
}

// A kernel's turn at pixel (x, y): interleaved gradient noise, a new one for each stage and frame.
FP_HD inline void turnOf(const Frame& f, int x, int y, int stage, float radius, float& c,
                         float& s) {
    const float turn = kTwoPi * ue::interleavedGradientNoise(float(x + 19 * stage) + 0.5f,
                                                             float(y + 47 * stage) + 0.5f,
                                                             f.frameMod8);
    float sn, cs;
    sinCos(turn, sn, cs);
    c = radius * cs;
    s = radius * sn;
}

// §12.5: pixel (x, y)'s kernel radius (its surface s) from its hit distance — the distance itself
// for diffuse signals, × α for reflections — in pixels of its own world size, clamped to [0, 8]; a
// miss (nothing near) takes the widest kernel, a mirror (α → 0) none; upscaling, at least k − 1.
FP_HD inline float kernelRadius(const Frame& f, const Surface& s, int x, int y) {
    if (!s.valid)
        return kNoRay;
    const PixelCoord t = f.coveringTexel(x, y);
    const float hit = f.hitDistance.at(t.x, t.y);
    // At full resolution a pixel without a ray keeps its value; upscaled, its neighbours fill it.
    if (hit < -1.5f)
        return f.upscale == 1 ? kNoRay : kMaxKernelPixels;
    float width = 1.0f;
    if (f.footprint == Footprint::Specular) {
        const float r = std::clamp(f.roughness.at(x, y), 0.0f, 1.0f);
        width = r * r;
    }
    const float world = hit < 0.0f ? 1e30f : hit;
    const float radius =
        std::clamp(world * width / std::max(s.radius, 1e-12f), 0.0f, float(kMaxKernelPixels)) *
        (width > 0.0f ? 1.0f : 0.0f);
    // Upscaling, the reconstruction must reach the texels around the pixel's own.
    return std::max(radius, float(f.upscale - 1));
}

// Reflections compare lobes too: a neighbour of another roughness reflects another blur
// (framepass's weight, §12.5).
FP_HD inline float lobeWeight(const Frame& f, int x, int y, int nx, int ny) {
    if (f.footprint != Footprint::Specular)
        return 1.0f;
    return saturate(1.0f - 4.0f * std::fabs(f.roughness.at(x, y) - f.roughness.at(nx, ny)));
}

// The reconstruction of a signal traced at 1/upscale resolution, at full-resolution pixel (x, y)
// (Unreal's denoiser upscales in this stage): the texel under the pixel and those under the
// Vogel taps around it, each weighed by the bilateral test of its own surface (the pixel it was
// traced at) against the pixel's; where none passes, the texel under the pixel as it is.
FP_HD inline void upscalePixel(const Frame& f, const Sources& src, const Targets& dst,
                               const Disc& disc, int x, int y) {
    if (!f.carriesSignal(x, y)) {
        for (int c = 0; c < f.channels; ++c)
            dst.plane[c].at(x, y) = 0.0f;
        return;
    }
    const Surface& ref = f.surfaces.at(x, y);
    float sum[kMaxSignalChannels] = {};
    float weight = 0.0f;
    auto add = [&](int px, int py) {
        if (px < 0 || py < 0 || px >= f.width || py >= f.height)
            return;
        const PixelCoord t = f.coveringTexel(px, py);
        if (!f.texelCarries(t.x, t.y))
            return;
        const Surface& s = f.texelSurface(t.x, t.y);
        const PixelCoord at = f.texelPixel(t.x, t.y);
        const float w = bilateralWeight(ref, s, std::min(ref.radius, s.radius) * kBilateralScale) *
                        lobeWeight(f, x, y, at.x, at.y);
        if (!(w > 0.0f))
            return;
        for (int c = 0; c < f.channels; ++c)
            sum[c] += w * src.plane[c].at(t.x, t.y);
        weight += w;
    };
    add(x, y);
    float c0, s0;
    turnOf(f, x, y, 0, f.radius.at(x, y), c0, s0);
    for (int i = 0; i < disc.taps; ++i) {
        const PixelCoord p = tapPixel(x, y, c0, s0, disc, i);
        add(p.x, p.y);
    }
    const PixelCoord under = f.coveringTexel(x, y);
    for (int c = 0; c < f.channels; ++c)
        dst.plane[c].at(x, y) = weight > 0.0f ? sum[c] / weight : src.plane[c].at(under.x, under.y);
}

/// One bilateral gather's settings: its disc, its stage (which turns the noise), and a fixed
/// radius in pixels (the history convolution) or the pixel's own (< 0).
struct Gather {
    Disc disc;
    int stage = 0;
    float fixedRadius = -1.0f;
};

// One bilateral gather at pixel (x, y): the centre and the disc's taps at the pixel's radius,
// turned by the stage's noise, each tap weighted by the bilateral test against the centre.
// Writes the weighted mean.
FP_HD inline void gatherPixel(const Frame& f, const Sources& src, const Targets& dst,
                              const Gather& g, int x, int y) {
    float sum[kMaxSignalChannels];
    for (int c = 0; c < f.channels; ++c)
        sum[c] = src.plane[c].at(x, y);
    const float r = g.fixedRadius >= 0.0f ? g.fixedRadius : f.radius.at(x, y);
    if (!f.carriesSignal(x, y) || r < 0.5f) {
        for (int c = 0; c < f.channels; ++c)
            dst.plane[c].at(x, y) = sum[c];
        return;
    }
    const Surface& ref = f.surfaces.at(x, y);
    float cs, sn;
    turnOf(f, x, y, g.stage, r, cs, sn);
    float weight = 1.0f;
    for (int i = 0; i < g.disc.taps; ++i) {
        const PixelCoord n = tapPixel(x, y, cs, sn, g.disc, i);
        if ((n.x == x && n.y == y) || n.x < 0 || n.y < 0 || n.x >= f.width || n.y >= f.height ||
            !f.carriesSignal(n.x, n.y))
            continue;
        const Surface& s = f.surfaces.at(n.x, n.y);
        const float w = bilateralWeight(ref, s, std::min(ref.radius, s.radius) * kBilateralScale) *
                        lobeWeight(f, x, y, n.x, n.y);
        if (w <= 0.0f)
            continue;
        for (int c = 0; c < f.channels; ++c)
            sum[c] += w * src.plane[c].at(n.x, n.y);
        weight += w;
    }
    for (int c = 0; c < f.channels; ++c)
        dst.plane[c].at(x, y) = sum[c] / weight;
}

// Mean and σ of the current signal on the "plus" set (the centre and its 4 edge neighbours),
// bilaterally weighted: the box the history is clamped to (§6.2 step 4).
FP_HD inline void neighbourhood(const Frame& f, const Sources& cur, int x, int y, float mean[],
                                float sigma[]) {
    const Surface& ref = f.surfaces.at(x, y);
    float m1[kMaxSignalChannels] = {}, m2[kMaxSignalChannels] = {}, wSum = 0.0f;
    const int plus[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (int i = 0; i < 5; ++i) {
        const int nx = x + plus[i][0], ny = y + plus[i][1];
        if (nx < 0 || ny < 0 || nx >= f.width || ny >= f.height || !f.carriesSignal(nx, ny))
            continue;
        const float w =
            i == 0 ? 1.0f : bilateralWeight(ref, f.surfaces.at(nx, ny), ref.radius * kBilateralScale);
        for (int c = 0; c < f.channels; ++c) {
            const float v = cur.plane[c].at(nx, ny);
            m1[c] += w * v;
            m2[c] += w * v * v;
        }
        wSum += w;
    }
    for (int c = 0; c < f.channels; ++c) {
        mean[c] = m1[c] / wSum;
        sigma[c] = std::sqrt(std::fabs(m2[c] / wSum - mean[c] * mean[c]));
    }
}

// The temporal accumulation at pixel (x, y) (§12.5, after §6.2's): reproject, take the nearest
// texel of last frame's state, validate it against the surface it stored, clamp it to this
// frame's neighbourhood box and blend by sample counts capped at the preset's target. Writes the
// result and the next state; returns whether the history contributed.
FP_HD inline bool accumulatePixel(const Frame& f, const Sources& cur, const Targets& dst, int x,
                                  int y) {
    float value[kMaxSignalChannels];
    for (int c = 0; c < f.channels; ++c)
        value[c] = cur.plane[c].at(x, y);
    float count = 1.0f;
    bool reused = false;
    const Surface& ref = f.surfaces.at(x, y);
    if (f.hasHistory() && f.carriesSignal(x, y)) {
        const double depth = f.depth.at(x, y);
        const PreviousPixel prev =
            reprojectPixelAtDepth(f.camera, x, y, depth, f.velocity, f.historyCamera);
        if (prev.onScreen({f.width, f.height})) {
            const int hx = std::clamp(int(prev.u), 0, f.width - 1);
            const int hy = std::clamp(int(prev.v), 0, f.height - 1);
            const float hCount = f.history[kCount].at(hx, hy);
            const CameraView& pc = f.historyCamera;
            const Vec3d hp = pc.translatedFromPixel(hx, hy, f.history[kViewDepth].at(hx, hy)) +
                             (pc.position - f.camera.position);
            const Vec3f hn{f.history[kNX].at(hx, hy), f.history[kNY].at(hx, hy),
                           f.history[kNZ].at(hx, hy)};
            const float valid =
                hCount > 0.0f ? bilateralWeight(ref, {float(hp.x), float(hp.y), float(hp.z)}, hn,
                                                ref.radius * kBilateralScale)
                              : 0.0f;
            if (valid > 0.0f) {
                float mean[kMaxSignalChannels], sigma[kMaxSignalChannels];
                neighbourhood(f, cur, x, y, mean, sigma);
                const float kept = std::min(hCount * valid, f.targetSamples - 1.0f);
                for (int c = 0; c < f.channels; ++c) {
                    const float past =
                        std::clamp(f.history[c].at(hx, hy), mean[c] - kClampSigma * sigma[c],
                                   mean[c] + kClampSigma * sigma[c]);
                    value[c] = (past * kept + value[c]) / (kept + 1.0f);
                }
                count = kept + 1.0f;
                reused = true;
            }
        }
    }
    for (int c = 0; c < f.channels; ++c)
        dst.plane[c].at(x, y) = value[c];
    if (f.state[0]) {
        for (int c = 0; c < kMaxSignalChannels; ++c)
            f.state[c].at(x, y) = c < f.channels ? value[c] : 0.0f;
        f.state[kCount].at(x, y) = f.carriesSignal(x, y) ? count : 0.0f;
        f.state[kViewDepth].at(x, y) = f.depth.at(x, y);
        f.state[kNX].at(x, y) = ref.normal.x;
        f.state[kNY].at(x, y) = ref.normal.y;
        f.state[kNZ].at(x, y) = ref.normal.z;
    }
    return reused;
}

// One gather sweep over the frame.
template <class Pixels>
void gather(const Pixels& pixels, const Frame& f, const Sources& src, const Targets& dst,
            const Gather& g) {
    pixels.template forEach<0>(
        f.width, f.height,
        [=] FP_HD(int x, int y, WorkCounts<0>&) { gatherPixel(f, src, dst, g, x, y); },
        "signal denoiser gather");
}

template <class TextureT>
Sources sourcesOf(const TextureT& t) {
    Sources s;
    for (int c = 0; c < t.image().channelCount() && c < kMaxSignalChannels; ++c)
        s.plane[c] = viewOf(t.image().plane(c));
    return s;
}

template <class TextureT>
Targets targetsOf(TextureT& t) {
    Targets s;
    for (int c = 0; c < t.image().channelCount() && c < kMaxSignalChannels; ++c)
        s.plane[c] = spanOf(t.image().plane(c));
    return s;
}

}  // namespace kernel

/// A denoising pass on either backend (PerPixel.h): the planes of `job.signalPorts` (in order)
/// make the signal; reads the `hitDistance` input, the GBuffer's depth, normal, shading model (and
/// roughness for reflections), the optional velocity and the pass's history; writes each signal
/// port's denoised output of the same name, keeps the next state when accumulating, and adds the
/// work counters (pixels, skippedPixels, historyPixels). Not `job.enabled` (the denoiser cvar at 0),
/// the raw signal goes through, point-upsampled where it was traced at a lower resolution.
template <class Ports, class Pixels>
void run(PassContext& ctx,
         const Ports& ports,
         const Pixels& pixels,
         const Denoising& job) {
    using namespace kernel;
    const Stages& stages = job.stages;
    const Extent size = ctx.frame().extent;
    const int W = size.width, H = size.height;
    Frame f{};
    f.width = W;
    f.height = H;
    Sources signal;
    Targets out;
    int channels = 0;
    Extent traced{};
    for (const std::string& port : job.signalPorts) {
        const auto& image = ports.input(port)->image();
        auto& result = ports.overwrite(port, {size}).image();
        if (channels == 0)
            traced = {image.width(), image.height()};
        FP_CHECK(image.width() == traced.width && image.height() == traced.height,
                 "the signal's planes are {}×{} and {}×{}", traced.width, traced.height,
                 image.width(), image.height());
        for (int c = 0; c < image.channelCount(); ++c, ++channels) {
            FP_CHECK(channels < kMaxSignalChannels, "a denoised signal has 1 to {} channels",
                     kMaxSignalChannels);
            signal.plane[channels] = viewOf(image.plane(c));
            out.plane[channels] = spanOf(result.plane(c));
        }
    }
    FP_CHECK(channels >= 1, "a denoised signal has 1 to {} channels (got 0)", kMaxSignalChannels);
    f.channels = channels;
    const int upscale = upscaleOf(size, traced);
    FP_CHECK(upscale > 0,
             "the signal is {}×{}: neither the frame's {}×{} nor its 1/2, 1/3 or 1/4 (a ray-traced "
             "pass's screen percentage)", traced.width, traced.height, W, H);
    f.upscale = upscale;
    f.traceWidth = traced.width;
    f.traceHeight = traced.height;

    if (!job.enabled) {
        pixels.template forEach<0>(
            W, H,
            [=] FP_HD(int x, int y, WorkCounts<0>&) {
                const PixelCoord t = f.coveringTexel(x, y);
                for (int c = 0; c < f.channels; ++c)
                    out.plane[c].at(x, y) = signal.plane[c].at(t.x, t.y);
            },
            "signal denoiser pass-through");
        return;
    }

    const auto& hit = ports.input(kHitDistance)->image();
    FP_CHECK(hit.width() == traced.width && hit.height() == traced.height,
             "hitDistance is {}×{} but the signal is {}×{}", hit.width(), hit.height(),
             traced.width, traced.height);
    f.hitDistance = viewOf(hit.plane(0));
    f.footprint = stages.footprint;
    f.targetSamples = stages.targetSamples;
    if (stages.footprint == Footprint::Specular) {
        const auto& roughness = ports.input(gbuffer::kRoughness)->image();
        FP_CHECK(roughness.width() == W && roughness.height() == H,
                 "roughness is {}×{} but the frame is {}×{}", roughness.width(), roughness.height(),
                 W, H);
        f.roughness = viewOf(roughness.plane(0));
    }
    const auto* velocity = ports.input(gbuffer::kVelocity);
    FP_CHECK(!velocity || (velocity->image().width() == W && velocity->image().height() == H),
             "velocity is {}×{} but the frame is {}×{}", velocity ? velocity->image().width() : 0,
             velocity ? velocity->image().height() : 0, W, H);
    f.velocity = velocityViewOf(velocity);
    f.camera = ctx.frame().camera.current;
    f.frameMod8 = ue::frameIndexMod8(ctx.frame().number);
    const auto& normal = ports.input(gbuffer::kNormal)->image();
    f.depth = viewOf(ports.input(gbuffer::kDepth)->image().plane(0));
    const SurfaceInputsView gbuffer{
        f.depth,
        {viewOf(normal.plane(0)), viewOf(normal.plane(1)), viewOf(normal.plane(2))},
        viewOf(ports.input(gbuffer::kShadingModel)->image().plane(0))};

    const auto surfaceMemory = ports.template scratchArray<Surface>(std::size_t(W) * H);
    f.surfaces = {surfaceMemory.get(), W, H, 1};
    decltype(ports.template scratchArray<Surface>(1)) traceMemory;
    if (upscale > 1) {
        traceMemory = ports.template scratchArray<Surface>(std::size_t(traced.width) * traced.height);
        f.traceSurfaces = {traceMemory.get(), traced.width, traced.height, upscale};
    }
    auto radius = ports.scratch({size}, {"R"});
    f.radius = spanOf(radius.image().plane(0));

    const bool temporal = stages.temporalAccumulation;
    const auto* past = temporal ? ports.historyState() : nullptr;
    if (past && past->image().width() == W && past->image().height() == H) {
        for (int c = 0; c < kStateChannels; ++c)
            f.history[c] = viewOf(past->image().plane(c));
        f.historyCamera = ctx.history()->camera;
    }
    using TextureT = std::decay_t<decltype(radius)>;
    TextureT state;
    if (temporal) {
        state = ports.scratch({size}, stateChannels());
        for (int c = 0; c < kStateChannels; ++c)
            f.state[c] = spanOf(state.image().plane(c));
    }

    // Each pixel's surface and, from it, its kernel radius in one sweep (a second would read
    // every surface back).
    const auto carried = pixels.template forEach<2>(
        W, H,
        [=] FP_HD(int x, int y, WorkCounts<2>& n) {
            const Surface s = f.surfaces.build(f.camera, gbuffer, NormalRead::Normalised, x, y);
            const float r = kernelRadius(f, s, x, y);
            f.radius.at(x, y) = r;
            ++n.value[r >= 0.0f ? 0 : 1];
        },
        "signal denoiser surfaces and radii");
    if (upscale > 1)
        pixels.template forEach<0>(
            traced.width, traced.height,
            [=] FP_HD(int x, int y, WorkCounts<0>&) {
                f.traceSurfaces.build(f.camera, gbuffer, NormalRead::Normalised, x, y);
            },
            "signal denoiser texel surfaces");

    // Reconstruction, then the pre-convolutions, ping-ponging between two scratch images.
    const std::vector<std::string> names(channels, "S");
    TextureT a = ports.scratch({size}, names), b = ports.scratch({size}, names);
    const int taps = std::clamp(stages.reconstructionSamples, 1, kMaxReconstructionSamples);
    if (upscale > 1) {
        const Disc disc = Disc::vogel(taps);
        const Targets dst = targetsOf(a);
        pixels.template forEach<0>(
            W, H,
            [=] FP_HD(int x, int y, WorkCounts<0>&) { upscalePixel(f, signal, dst, disc, x, y); },
            "signal denoiser reconstruction");
    }
    if (upscale == 1)
        gather(pixels, f, signal, targetsOf(a), {Disc::vogel(taps), 0});
    TextureT* cur = &a;
    TextureT* next = &b;
    for (int i = 0; i < stages.preConvolutions; ++i) {
        gather(pixels, f, sourcesOf(*cur), targetsOf(*next),
               {Disc::vogel(kPreConvolutionSamples), 1 + i});
        std::swap(cur, next);
    }

    // Temporal accumulation, then the history convolution (a post filter on what accumulated).
    const bool convolveHistory = stages.historyConvolutionSamples > 0;
    const Targets accumulated = convolveHistory ? targetsOf(*next) : out;
    const Sources current = sourcesOf(*cur);
    const auto reused = pixels.template forEach<1>(
        W, H,
        [=] FP_HD(int x, int y, WorkCounts<1>& n) {
            n.value[0] += accumulatePixel(f, current, accumulated, x, y);
        },
        "signal denoiser accumulation");
    if (convolveHistory)
        gather(pixels, f, sourcesOf(*next), out,
               {Disc::vogel(stages.historyConvolutionSamples), 8, stages.historyConvolutionSpread});
    ctx.addWork("pixels", carried[0]);
    ctx.addWork("skippedPixels", carried[1]);
    ctx.addWork("historyPixels", reused[0]);
    if (temporal)
        ports.keepHistory(std::move(state));
}

}  // namespace fp::ssd
