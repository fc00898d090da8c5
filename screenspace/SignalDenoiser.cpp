#include "screenspace/SignalDenoiser.h"

#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/Tiles.h"
#include "foundation/UnrealRandom.h"
#include "screenspace/Bilateral.h"
#include "screenspace/GBuffer.h"
#include "screenspace/TraceResolution.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>

namespace fp::ssd {

namespace {

constexpr float kGoldenAngle = 2.39996323f;
constexpr float kTwoPi = 6.28318531f;
// The plane-distance tolerance of every stage: the smaller pixel world radius × 2√2 × 3, the
// diffuse preset of the SSGI denoiser (algorithms §6.2).
constexpr float kBilateralScale = 2.0f * 1.41421356f * 3.0f;
constexpr float kClampSigma = 1.25f;  // the history's neighbourhood box, as SSGI's (§6.2 step 4)
constexpr int kPreConvolutionSamples = 8;
// A pixel whose input carries no ray (hit distance < −1.5): it keeps its value and no kernel reads it.
constexpr float kNoRay = -1.0f;

enum StateChannel { kCount = kMaxSignalChannels, kViewDepth, kNX, kNY, kNZ, kStateChannels };

struct Frame {
    const Stages& stages;
    const Inputs& in;
    int channels;
    int width, height;
    SurfaceGrid surfaces;
    Plane radius;  // kernel radius, pixels; kNoRay where the pixel passes through
    uint32_t frameMod8;
    // A signal traced at a lower resolution (a ray-traced pass's screen percentage): each texel
    // stands for the top-left pixel of its upscale × upscale block (fullResPixel).
    int upscale = 1;
    int traceWidth = 0, traceHeight = 0;
    std::optional<SurfaceGrid> traceSurfaces{};  // the texels' surfaces, when upscale > 1
    VelocityView velocity{};                     // the optional motion the history reprojects by

    bool carriesSignal(int x, int y) const { return radius.at(x, y) >= 0.0f; }
    const Surface& texelSurface(int tx, int ty) const {
        return traceSurfaces ? traceSurfaces->at(tx, ty) : surfaces.at(tx, ty);
    }
    // A texel whose ray was traced (a surface, and a hit distance above −1.5).
    bool texelCarries(int tx, int ty) const {
        return texelSurface(tx, ty).valid && in.hitDistance->at(tx, ty) >= -1.5f;
    }
    PixelCoord texelPixel(int tx, int ty) const {
        return fullResPixel(tx, ty, upscale, width, height);
    }
    // The texel a frame pixel lies in.
    PixelCoord coveringTexel(int x, int y) const {
        return {std::min(x / upscale, traceWidth - 1), std::min(y / upscale, traceHeight - 1)};
    }
};

struct Offset {
    float x, y;
};

// `taps` points spread evenly over the unit disc (Vogel's spiral: radius √((i + ½)/n), each turned
// by the golden angle from the one before).
std::vector<Offset> vogelDisc(int taps) {
    std::vector<Offset> disc(taps);
    for (int i = 0; i < taps; ++i) {
        const float d = std::sqrt((float(i) + 0.5f) / float(taps));
        disc[i] = {d * std::cos(kGoldenAngle * float(i)), d * std::sin(kGoldenAngle * float(i))};
    }
    return disc;
}

// The pixel under disc offset `o` turned and scaled by (cosine, sine) × radius about pixel (x, y).
PixelCoord tapPixel(int x, int y, float cosR, float sinR, const Offset& o) {
    return {int(std::floor(float(x) + 0.5f + cosR * o.x - sinR * o.y)),
            int(std::floor(float(y) + 0.5f + sinR * o.x + cosR * o.y))};
}

// §12.5: the pixel's kernel radius from its hit distance — the distance itself for diffuse
// signals, × α for reflections — in pixels of its own world size, clamped to [0, 8]; a miss
// (nothing near) takes the widest kernel, a mirror (α → 0) none; upscaling, at least k − 1.
float kernelRadius(const Frame& f, int x, int y) {
    const Surface& s = f.surfaces.at(x, y);
    if (!s.valid)
        return kNoRay;
    const PixelCoord t = f.coveringTexel(x, y);
    const float hit = f.in.hitDistance->at(t.x, t.y);
    // At full resolution a pixel without a ray keeps its value; upscaled, its neighbours fill it.
    if (hit < -1.5f)
        return f.upscale == 1 ? kNoRay : kMaxKernelPixels;
    float width = 1.0f;
    if (f.stages.footprint == Footprint::Specular) {
        const float r = std::clamp(f.in.roughness->at(x, y), 0.0f, 1.0f);
        width = r * r;
    }
    const float world = hit < 0.0f ? 1e30f : hit;
    const float radius =
        std::clamp(world * width / std::max(s.radius, 1e-12f), 0.0f, kMaxKernelPixels) *
        (width > 0.0f ? 1.0f : 0.0f);
    // Upscaling, the reconstruction must reach the texels around the pixel's own.
    return std::max(radius, float(f.upscale - 1));
}

// Reflections compare lobes too: a neighbour of another roughness reflects another blur
// (framepass's weight, §12.5).
float lobeWeight(const Frame& f, int x, int y, int nx, int ny) {
    if (f.stages.footprint != Footprint::Specular)
        return 1.0f;
    return saturate(1.0f - 4.0f * std::fabs(f.in.roughness->at(x, y) - f.in.roughness->at(nx, ny)));
}

// The reconstruction of a signal traced at 1/upscale resolution, at every full-resolution pixel
// (Unreal's denoiser upscales in this stage): the texel under the pixel and those under the
// Vogel taps around it, each weighed by the bilateral test of its own surface (the pixel it was
// traced at) against the pixel's; where none passes, the texel under the pixel as it is.
void upscaleGather(const Frame& f, const std::vector<const Plane*>& src,
                   const std::vector<Plane*>& dst, int taps) {
    const std::vector<Offset> disc = vogelDisc(taps);
    forEachTile(f.width, f.height, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (!f.carriesSignal(x, y)) {
                    for (int c = 0; c < f.channels; ++c)
                        dst[c]->at(x, y) = 0.0f;
                    continue;
                }
                const Surface& ref = f.surfaces.at(x, y);
                float sum[kMaxSignalChannels] = {};
                float weight = 0.0f;
                auto add = [&](int px, int py) {
                    if (px < 0 || py < 0 || px >= f.width || py >= f.height)
                        return;
                    const auto [tx, ty] = f.coveringTexel(px, py);
                    if (!f.texelCarries(tx, ty))
                        return;
                    const Surface& s = f.texelSurface(tx, ty);
                    const PixelCoord at = f.texelPixel(tx, ty);
                    const float w =
                        bilateralWeight(ref, s, std::min(ref.radius, s.radius) * kBilateralScale) *
                        lobeWeight(f, x, y, at.x, at.y);
                    if (!(w > 0.0f))
                        return;
                    for (int c = 0; c < f.channels; ++c)
                        sum[c] += w * src[c]->at(tx, ty);
                    weight += w;
                };
                add(x, y);
                const float r = f.radius.at(x, y);
                const float turn = kTwoPi * ue::interleavedGradientNoise(float(x) + 0.5f,
                                                                         float(y) + 0.5f, f.frameMod8);
                const float c0 = r * std::cos(turn), s0 = r * std::sin(turn);
                for (int i = 0; i < taps; ++i) {
                    const PixelCoord p = tapPixel(x, y, c0, s0, disc[i]);
                    add(p.x, p.y);
                }
                const PixelCoord under = f.coveringTexel(x, y);
                for (int c = 0; c < f.channels; ++c)
                    dst[c]->at(x, y) =
                        weight > 0.0f ? sum[c] / weight : src[c]->at(under.x, under.y);
            }
    });
}

// One bilateral gather: the centre and `taps` taps on a Vogel disc of radius `radius` pixels,
// turned by a per-pixel angle (interleaved gradient noise, a new one for each stage and frame);
// each tap weighted by the bilateral test against the centre. Writes the weighted mean.
void gather(const Frame& f, const std::vector<const Plane*>& src, const std::vector<Plane*>& dst,
            int taps, int stage, bool fixedRadius, float fixedRadiusPixels) {
    const std::vector<Offset> disc = vogelDisc(taps);
    forEachTile(f.width, f.height, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                float sum[kMaxSignalChannels];
                for (int c = 0; c < f.channels; ++c)
                    sum[c] = src[c]->at(x, y);
                const float r = fixedRadius ? fixedRadiusPixels : f.radius.at(x, y);
                if (!f.carriesSignal(x, y) || r < 0.5f) {
                    for (int c = 0; c < f.channels; ++c)
                        dst[c]->at(x, y) = sum[c];
                    continue;
                }
                const Surface& ref = f.surfaces.at(x, y);
                const float turn =
                    kTwoPi * ue::interleavedGradientNoise(float(x + 19 * stage) + 0.5f,
                                                          float(y + 47 * stage) + 0.5f, f.frameMod8);
                const float c = r * std::cos(turn), sn = r * std::sin(turn);
                float weight = 1.0f;
                for (int i = 0; i < taps; ++i) {
                    const auto [nx, ny] = tapPixel(x, y, c, sn, disc[i]);
                    if ((nx == x && ny == y) || nx < 0 || ny < 0 || nx >= f.width ||
                        ny >= f.height || !f.carriesSignal(nx, ny))
                        continue;
                    const Surface& s = f.surfaces.at(nx, ny);
                    const float w =
                        bilateralWeight(ref, s, std::min(ref.radius, s.radius) * kBilateralScale) *
                        lobeWeight(f, x, y, nx, ny);
                    if (w <= 0.0f)
                        continue;
                    for (int c = 0; c < f.channels; ++c)
                        sum[c] += w * src[c]->at(nx, ny);
                    weight += w;
                }
                for (int c = 0; c < f.channels; ++c)
                    dst[c]->at(x, y) = sum[c] / weight;
            }
    });
}

// Mean and σ of the current signal on the "plus" set (the centre and its 4 edge neighbours),
// bilaterally weighted: the box the history is clamped to (§6.2 step 4).
void neighbourhood(const Frame& f, const std::vector<const Plane*>& cur, int x, int y,
                   float mean[], float sigma[]) {
    const Surface& ref = f.surfaces.at(x, y);
    float m1[kMaxSignalChannels] = {}, m2[kMaxSignalChannels] = {}, wSum = 0.0f;
    const int plus[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& o : plus) {
        const int nx = x + o[0], ny = y + o[1];
        if (nx < 0 || ny < 0 || nx >= f.width || ny >= f.height || !f.carriesSignal(nx, ny))
            continue;
        const float w = (nx == x && ny == y)
                            ? 1.0f
                            : bilateralWeight(ref, f.surfaces.at(nx, ny), ref.radius * kBilateralScale);
        for (int c = 0; c < f.channels; ++c) {
            const float v = cur[c]->at(nx, ny);
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

// The temporal accumulation (§12.5, after §6.2's): reproject, take the nearest texel of last
// frame's state, validate it against the surface it stored, clamp it to this frame's
// neighbourhood box and blend by sample counts capped at the preset's target. Writes the result
// and the next state; returns whether the history contributed.
bool accumulate(const Frame& f, const std::vector<const Plane*>& cur, const Image* history,
                const std::vector<Plane*>& dst, Image* state, int x, int y) {
    float value[kMaxSignalChannels];
    for (int c = 0; c < f.channels; ++c)
        value[c] = cur[c]->at(x, y);
    float count = 1.0f;
    bool reused = false;
    const Surface& ref = f.surfaces.at(x, y);
    if (history && f.carriesSignal(x, y)) {
        const double depth = f.in.gbuffer.depth.at(x, y);
        const PreviousPixel prev =
            reprojectPixelAtDepth(f.in.camera, x, y, depth, f.velocity, *f.in.historyCamera);
        const Image& h = *history;
        if (prev.onScreen({f.width, f.height})) {
            const int hx = std::clamp(int(prev.u), 0, f.width - 1);
            const int hy = std::clamp(int(prev.v), 0, f.height - 1);
            const float hCount = h.plane(kCount).at(hx, hy);
            const CameraView& pc = *f.in.historyCamera;
            const Vec3d hp = pc.translatedFromPixel(hx, hy, h.plane(kViewDepth).at(hx, hy)) +
                             (pc.position - f.in.camera.position);
            const Vec3f hn{h.plane(kNX).at(hx, hy), h.plane(kNY).at(hx, hy), h.plane(kNZ).at(hx, hy)};
            const float valid =
                hCount > 0.0f ? bilateralWeight(ref, {float(hp.x), float(hp.y), float(hp.z)}, hn,
                                                ref.radius * kBilateralScale)
                              : 0.0f;
            if (valid > 0.0f) {
                float mean[kMaxSignalChannels], sigma[kMaxSignalChannels];
                neighbourhood(f, cur, x, y, mean, sigma);
                const float kept = std::min(hCount * valid, f.stages.targetSamples - 1.0f);
                for (int c = 0; c < f.channels; ++c) {
                    const float past = std::clamp(h.plane(c).at(hx, hy), mean[c] - kClampSigma * sigma[c],
                                                  mean[c] + kClampSigma * sigma[c]);
                    value[c] = (past * kept + value[c]) / (kept + 1.0f);
                }
                count = kept + 1.0f;
                reused = true;
            }
        }
    }
    for (int c = 0; c < f.channels; ++c)
        dst[c]->at(x, y) = value[c];
    if (state) {
        for (int c = 0; c < kMaxSignalChannels; ++c)
            state->plane(c).at(x, y) = c < f.channels ? value[c] : 0.0f;
        state->plane(kCount).at(x, y) = f.carriesSignal(x, y) ? count : 0.0f;
        state->plane(kViewDepth).at(x, y) = f.in.gbuffer.depth.at(x, y);
        state->plane(kNX).at(x, y) = ref.normal.x;
        state->plane(kNY).at(x, y) = ref.normal.y;
        state->plane(kNZ).at(x, y) = ref.normal.z;
    }
    return reused;
}

std::vector<const Plane*> constPlanes(const Image& image) {
    std::vector<const Plane*> p;
    for (int c = 0; c < image.channelCount(); ++c)
        p.push_back(&image.plane(c));
    return p;
}

std::vector<Plane*> planes(Image& image) {
    std::vector<Plane*> p;
    for (int c = 0; c < image.channelCount(); ++c)
        p.push_back(&image.plane(c));
    return p;
}

}  // namespace

int upscaleOf(Extent frame, Extent signal) {
    for (int k = 1; k <= 4; ++k)
        if (traceExtent(frame, k) == signal)
            return k;
    return 0;
}

const std::vector<std::string>& stateChannels() {
    static const std::vector<std::string> names = {"R", "G", "B", "A", "N", "D", "NX", "NY", "NZ"};
    return names;
}

Counts denoise(const Stages& stages,
               const Inputs& in,
               const std::vector<Plane*>& out,
               Image* state) {
    const int channels = int(in.signal.size());
    FP_CHECK(channels >= 1 && channels <= kMaxSignalChannels && int(out.size()) == channels,
             "a denoised signal has 1 to {} channels (got {})", kMaxSignalChannels, channels);
    FP_CHECK(in.hitDistance, "the denoiser sizes its kernels from the rays' hit distance");
    FP_CHECK(stages.footprint != Footprint::Specular || in.roughness,
             "the reflection denoiser needs the GBuffer's roughness");
    const int W = in.gbuffer.depth.width(), H = in.gbuffer.depth.height();
    const int upscale = upscaleOf({W, H}, {in.signal[0]->width(), in.signal[0]->height()});
    FP_CHECK(upscale > 0,
             "the signal is {}×{}: neither the frame's {}×{} nor its 1/2, 1/3 or 1/4 (a ray-traced "
             "pass's screen percentage)", in.signal[0]->width(), in.signal[0]->height(), W, H);
    const int TW = in.signal[0]->width(), TH = in.signal[0]->height();
    for (const Plane* p : in.signal)
        FP_CHECK(p->width() == TW && p->height() == TH, "the signal's planes are {}×{} and {}×{}", TW,
                 TH, p->width(), p->height());
    FP_CHECK(in.hitDistance->width() == TW && in.hitDistance->height() == TH,
             "hitDistance is {}×{} but the signal is {}×{}", in.hitDistance->width(),
             in.hitDistance->height(), TW, TH);
    FP_CHECK(!in.roughness || (in.roughness->width() == W && in.roughness->height() == H),
             "roughness is {}×{} but the frame is {}×{}", in.roughness ? in.roughness->width() : 0,
             in.roughness ? in.roughness->height() : 0, W, H);
    FP_CHECK(!in.velocity || (in.velocity->image().width() == W && in.velocity->image().height() == H),
             "velocity is {}×{} but the frame is {}×{}", in.velocity ? in.velocity->image().width() : 0,
             in.velocity ? in.velocity->image().height() : 0, W, H);

    Frame f{stages,
            in,
            channels,
            W,
            H,
            SurfaceGrid(in.camera, in.gbuffer, {W, H}, 1, NormalRead::Normalised),
            Plane(W, H),
            ue::frameIndexMod8(in.frameNumber)};
    f.velocity = velocityViewOf(in.velocity);
    f.upscale = upscale;
    f.traceWidth = TW;
    f.traceHeight = TH;
    if (upscale > 1)
        f.traceSurfaces.emplace(in.camera, in.gbuffer, Extent{TW, TH}, upscale,
                                NormalRead::Normalised);
    std::atomic<uint64_t> pixels{0}, skipped{0};
    forEachTile(W, H, [&](const Tile& t) {
        uint64_t n = 0, s = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const float r = kernelRadius(f, x, y);
                f.radius.at(x, y) = r;
                ++(r >= 0.0f ? n : s);
            }
        pixels += n;
        skipped += s;
    });

    // Reconstruction, then the pre-convolutions, ping-ponging between two scratch images.
    std::vector<std::string> names(channels, "S");
    Image a(W, H, names), b(W, H, names);
    const int taps = std::clamp(stages.reconstructionSamples, 1, kMaxReconstructionSamples);
    if (upscale > 1)
        upscaleGather(f, in.signal, planes(a), taps);
    else
        gather(f, in.signal, planes(a), taps, 0, false, 0.0f);
    Image* cur = &a;
    Image* next = &b;
    for (int i = 0; i < stages.preConvolutions; ++i) {
        gather(f, constPlanes(*cur), planes(*next), kPreConvolutionSamples, 1 + i, false, 0.0f);
        std::swap(cur, next);
    }

    // Temporal accumulation, then the history convolution (a post filter on what accumulated).
    const bool convolveHistory = stages.historyConvolutionSamples > 0;
    const std::vector<Plane*> accumulated = convolveHistory ? planes(*next) : out;
    std::atomic<uint64_t> reused{0};
    const bool temporal = stages.temporalAccumulation;
    const Image* history = temporal && in.history && in.historyCamera ? in.history : nullptr;
    Image* keep = temporal ? state : nullptr;
    const std::vector<const Plane*> current = constPlanes(*cur);
    forEachTile(W, H, [&](const Tile& t) {
        uint64_t n = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x)
                n += accumulate(f, current, history, accumulated, keep, x, y);
        reused += n;
    });
    if (convolveHistory)
        gather(f, constPlanes(*next), out, stages.historyConvolutionSamples, 8, true,
               stages.historyConvolutionSpread);
    return {pixels.load(), skipped.load(), reused.load()};
}

std::vector<PortSpec> denoiserInputs(Footprint footprint) {
    std::vector<PortSpec> in = {
        {.name = kHitDistance,
         .channels = {"Y"},
         .doc = "the rays' hit distance, scene units, as the tracing pass wrote it (sizes the "
                "kernels; −1 no hit, −2 no ray: passed through)"},
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit and sky pixels pass through"),
        gbuffer::velocityInput(
            "optional motion for reprojection; the history's camera is used when unbound"),
    };
    if (footprint == Footprint::Specular)
        in.push_back(gbuffer::roughnessInput("sizes the kernel with the lobe (α = roughness²)"));
    return in;
}

PassMemory memoryOf(Extent frame, int channels, bool enabled, bool temporalAccumulation) {
    if (!enabled) return {};
    const std::size_t state = temporalAccumulation ? imageBytes(frame, int(stateChannels().size())) : 0;
    const std::size_t grid = sizeof(Surface) * std::size_t(frame.width) * std::size_t(frame.height);
    return {grid + imageBytes(frame, 1) + 2 * imageBytes(frame, channels) + state, state};
}

void denoisePorts(PassContext& ctx,
                  const Stages& stages,
                  const std::vector<std::string>& signalPorts,
                  bool enabled) {
    const Extent size = ctx.frame().extent;
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    Inputs in{.gbuffer = {depth, ctx.input(gbuffer::kNormal)->image(),
                          ctx.input(gbuffer::kShadingModel)->image().plane(0)}};
    std::vector<Plane*> out;
    for (const std::string& port : signalPorts) {
        const Image& image = ctx.input(port)->image();
        Image& result = ctx.output(port, {size}).image();
        for (int c = 0; c < image.channelCount(); ++c) {
            in.signal.push_back(&image.plane(c));
            out.push_back(&result.plane(c));
        }
    }
    if (!enabled) {  // the raw signal, point-upsampled where it was traced at a lower resolution
        const Extent traced{in.signal[0]->width(), in.signal[0]->height()};
        const int k = upscaleOf(size, traced);
        FP_CHECK(k > 0, "the signal is {}×{}: neither the frame's {}×{} nor its 1/2, 1/3 or 1/4",
                 traced.width, traced.height, size.width, size.height);
        for (std::size_t c = 0; c < out.size(); ++c)
            for (int y = 0; y < size.height; ++y)
                for (int x = 0; x < size.width; ++x)
                    out[c]->at(x, y) = in.signal[c]->at(std::min(x / k, traced.width - 1),
                                                        std::min(y / k, traced.height - 1));
        return;
    }
    in.hitDistance = &ctx.input(kHitDistance)->image().plane(0);
    if (stages.footprint == Footprint::Specular)
        in.roughness = &ctx.input(gbuffer::kRoughness)->image().plane(0);
    in.velocity = ctx.input(gbuffer::kVelocity);
    in.camera = ctx.frame().camera.current;
    in.frameNumber = ctx.frame().number;
    const PassHistory* past = stages.temporalAccumulation ? ctx.history() : nullptr;
    if (past && past->state.image().width() == size.width &&
        past->state.image().height() == size.height) {
        in.history = &past->state.image();
        in.historyCamera = &past->camera;
    }
    Image state;
    if (stages.temporalAccumulation)
        state = Image(size.width, size.height, stateChannels());
    const Counts n = denoise(stages, in, out, stages.temporalAccumulation ? &state : nullptr);
    ctx.addWork("pixels", n.pixels);
    ctx.addWork("skippedPixels", n.skippedPixels);
    ctx.addWork("historyPixels", n.historyPixels);
    if (stages.temporalAccumulation)
        ctx.keepHistory(Texture(std::move(state)));
}

}  // namespace fp::ssd
