#pragma once
// SSGI denoiser's per-pixel work (algorithms §6.2), written once for both backends: SSGIDenoisePass
// runs it with CpuPixels from execute(), SSGIDenoisePass.cu with CudaPixels. Three sweeps over
// the trace grid — surfaces, the spatial reconstruction, the temporal accumulation — each
// reading only what the sweep before it wrote.
#include "screenspace/Bilateral.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Reprojection.h"
#include "screenspace/Surface.h"
#include "screenspace/TraceResolution.h"
#include "foundation/Error.h"
#include "foundation/FloatToInt.h"
#include "foundation/HostDevice.h"
#include "framework/Pass.h"
#include "foundation/PerPixel.h"
#include "foundation/PlaneView.h"
#include "foundation/UnrealRandom.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

namespace fp::ssgi_denoise {

inline constexpr const char* kDiffuse = "diffuse";
inline constexpr const char* kAo = "ao";
inline constexpr const char* kHistoryValidity = "historyValidity";

constexpr int kTracks = 4;  // one per pixel of a 2×2 quad
constexpr int kTaps = 8;    // reconstruction samples besides the centre
constexpr float kClampSigma = 1.25f;
constexpr float kTargetSamples = 128.0f;
constexpr float kHistoryCap = 64.0f;  // R8 storage of SampleCount/64
// algorithms §6.2: bilateral distance = pixel world radius × 2√2 × 3 (the SSGI multiplier); the
// history test uses the same multiplier (max(3, 3)).
constexpr float kBilateralScale = 2.0f * 1.41421356f * 3.0f;

struct Offset {
    float x, y;  // from the quad centre, pixels (half-integers)
};
/// The reconstruction kernel: per track, 8 pixel offsets from the centre of the 2×2 quad.
struct KernelTable {
    Offset tap[kTracks][kTaps];
};

/// Unreal's Stackowiak tables are not transcribed (algorithms §13.1). framepass builds the same
/// kind of set [inferred]: the pixels of an 8×8 block around the quad centre, quad excluded,
/// ordered by radius then angle and dealt round-robin to the four tracks, so each pixel of the
/// quad sees its own 8 taps, balanced around the centre, out to 2.5·√2 pixels.
inline const KernelTable& kernelTable() {
    static const KernelTable table = [] {
        struct Candidate {
            float x, y, r2, angle;
        };
        std::vector<Candidate> c;
        for (int b = -4; b < 4; ++b)
            for (int a = -4; a < 4; ++a) {
                const float x = float(a) + 0.5f, y = float(b) + 0.5f;
                if (std::fabs(x) < 1.0f && std::fabs(y) < 1.0f)
                    continue;
                c.push_back({x, y, x * x + y * y, std::atan2(y, x)});
            }
        std::stable_sort(c.begin(), c.end(), [](const Candidate& p, const Candidate& q) {
            return p.r2 != q.r2 ? p.r2 < q.r2 : p.angle < q.angle;
        });
        KernelTable t{};
        for (int i = 0; i < kTracks * kTaps; ++i)
            t.tap[i % kTracks][i / kTracks] = {c[i].x, c[i].y};
        return t;
    }();
    return table;
}

// History state channels, per trace pixel.
enum HistoryChannel { kR, kG, kB, kAO, kCount, kViewDepth, kNX, kNY, kNZ, kHistoryChannels };
inline const std::vector<std::string>& historyChannels() {
    static const std::vector<std::string> names = {"R", "G", "B", "AO", "N", "D", "NX", "NY", "NZ"};
    return names;
}
// The reconstruction's channels: R G B AO normalised, N the accumulated weight.
enum ReconChannel { kReconCount = 4, kReconChannels = 5 };

/// Everything the three sweeps read and write. Absent images have null data.
struct Frame {
    CameraView cam;
    SurfaceInputsView gbuffer;
    SurfaceGridView surfaces;
    KernelTable kernel;
    PlaneView color[3], ao, depth;
    VelocityView velocity;
    PlaneSpan recon[kReconChannels];
    PlaneSpan outColor[3], outAo, validity;
    // Temporal: last frame's state (null without a usable one), its camera, this frame's state.
    bool temporal;
    PlaneView hist[kHistoryChannels];
    CameraView prevCam;
    PlaneSpan state[kHistoryChannels];
    Extent full;
    int toFull;
    uint32_t frameMod8;

    FP_HD bool hasHistory() const { return hist[0].data != nullptr; }
};

// One of the four bilinear texels (00, 10, 01, 11), chosen with probability equal to its weight.
FP_HD inline int pickTexel(const float w[4], float u) {
    float acc = 0.0f;
    for (int i = 0; i < 3; ++i)
        if (u < (acc += w[i]))
            return i;
    return 3;
}

// Reconstruction (algorithms §6.2): the centre and the 8 taps of its track, bilaterally weighted
// against the centre's surface with the smaller of the two pixel radii (MIN_METADATA), summed as
// moment-1 sums. Writes R G B AO (normalised) and the accumulated sample count; false when the
// pixel has no surface and passes through as it is.
FP_HD inline bool reconstructPixel(const Frame& f, int x, int y) {
    const int TW = f.ao.width, TH = f.ao.height;
    const Surface& ref = f.surfaces.at(x, y);
    if (!ref.valid) {
        for (int c = 0; c < 3; ++c)
            f.recon[c].at(x, y) = f.color[c].at(x, y);
        f.recon[3].at(x, y) = f.ao.at(x, y);
        return false;
    }
    float sum[4] = {f.color[0].at(x, y), f.color[1].at(x, y), f.color[2].at(x, y), f.ao.at(x, y)};
    float weight = 1.0f;  // the centre sample
    const Offset* track = f.kernel.tap[(x & 1) + 2 * (y & 1)];
    const float qx = float(x & ~1) + 0.5f, qy = float(y & ~1) + 0.5f;
    for (int i = 0; i < kTaps; ++i) {
        const int nx = int(qx + track[i].x), ny = int(qy + track[i].y);
        if (nx < 0 || ny < 0 || nx >= TW || ny >= TH)
            continue;
        const Surface& s = f.surfaces.at(nx, ny);
        if (!s.valid)
            continue;
        const float w = bilateralWeight(ref, s, std::min(ref.radius, s.radius) * kBilateralScale);
        if (w <= 0.0f)
            continue;
        for (int c = 0; c < 3; ++c)
            sum[c] += w * f.color[c].at(nx, ny);
        sum[3] += w * f.ao.at(nx, ny);
        weight += w;
    }
    for (int c = 0; c < 4; ++c)
        f.recon[c].at(x, y) = sum[c] / weight;
    f.recon[kReconCount].at(x, y) = weight;
    return true;
}

// The history texel a pixel reads and its stored sample count (0: off screen or empty).
struct HistoryTap {
    int x, y;
    float count;
};

// algorithms §6.2 steps 1–3: reproject, then one texel of the bilinear 2×2 footprint picked by IGN.
FP_HD inline HistoryTap pickHistoryTexel(const Frame& f, int x, int y, int px, int py,
                                         const Surface& ref) {
    const int TW = f.ao.width, TH = f.ao.height;
    const Vec3d p{ref.position.x, ref.position.y, ref.position.z};
    const PreviousPixel prev = reprojectPixel(px, py, p, f.cam.position, f.velocity, f.prevCam);
    const double tu = prev.u / f.toFull - 0.5, tv = prev.v / f.toFull - 0.5;
    // Far off screen (or NaN) only the clamped edge texel is read, and then with no weight.
    const int x0 = floorToInt(tu, -2, TW + 1), y0 = floorToInt(tv, -2, TH + 1);
    const float fx = std::isfinite(tu) ? std::clamp(float(tu - x0), 0.0f, 1.0f) : 0.0f;
    const float fy = std::isfinite(tv) ? std::clamp(float(tv - y0), 0.0f, 1.0f) : 0.0f;
    const float u = ue::interleavedGradientNoise(float(x) + 0.5f, float(y) + 0.5f, f.frameMod8);
    const float w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    const int pick = pickTexel(w, u);
    const int hx = x0 + (pick & 1), hy = y0 + (pick >> 1);
    const int cx = std::clamp(hx, 0, TW - 1), cy = std::clamp(hy, 0, TH - 1);
    return {cx, cy, prev.onScreen(f.full) ? f.hist[kCount].at(cx, cy) : 0.0f};
}

// Bilateral validation of the history texel against its own surface (algorithms §6.2 step 3,
// history multiplier max(3, 3) = 3), rebuilt from the depth and normal the history kept.
FP_HD inline float historyWeight(const Frame& f, const Surface& ref, int cx, int cy) {
    const double hd = f.hist[kViewDepth].at(cx, cy);
    const PixelCoord hpx = fullResPixel(cx, cy, f.toFull, f.full.width, f.full.height);
    const Vec3d hp = f.prevCam.translatedFromPixel(hpx.x, hpx.y, hd) +
                     (f.prevCam.position - f.cam.position);
    const Vec3f hn{f.hist[kNX].at(cx, cy), f.hist[kNY].at(cx, cy), f.hist[kNZ].at(cx, cy)};
    return bilateralWeight(ref, {float(hp.x), float(hp.y), float(hp.z)}, hn,
                           ref.radius * kBilateralScale);
}

// algorithms §6.2 step 4: mean and σ of the current reconstruction on the "plus" set (centre + 4
// edge neighbours), bilaterally weighted with the centre's own radius.
FP_HD inline void neighbourhoodStats(const Frame& f, const Surface& ref, int x, int y,
                                     float mean[4], float sigma[4]) {
    const int TW = f.ao.width, TH = f.ao.height;
    float m1[4] = {0, 0, 0, 0}, m2[4] = {0, 0, 0, 0}, wSum = 0.0f;
    const int plus[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (int i = 0; i < 5; ++i) {
        const int nx = x + plus[i][0], ny = y + plus[i][1];
        if (nx < 0 || ny < 0 || nx >= TW || ny >= TH)
            continue;
        const Surface& s = f.surfaces.at(nx, ny);
        if (!s.valid)
            continue;
        const float w = i == 0 ? 1.0f : bilateralWeight(ref, s, ref.radius * kBilateralScale);
        for (int c = 0; c < 4; ++c) {
            const float v = f.recon[c].at(nx, ny);
            m1[c] += w * v;
            m2[c] += w * v * v;
        }
        wSum += w;
    }
    for (int c = 0; c < 4; ++c) {
        mean[c] = m1[c] / wSum;
        sigma[c] = std::sqrt(std::fabs(m2[c] / wSum - mean[c] * mean[c]));
    }
}

// One trace pixel after temporal accumulation.
struct Accumulated {
    float value[4];  // R G B AO
    float count;     // samples behind it
    float kept;      // share of the history's samples kept (the validity debug output)
    bool reused;     // the history contributed
};

// algorithms §6.2 steps 1–6 for one pixel: the reconstruction alone when there is no valid history,
// else the clamped history blended with it by sample counts.
FP_HD inline Accumulated accumulatePixel(const Frame& f, int x, int y) {
    const Surface& ref = f.surfaces.at(x, y);
    const PixelCoord traced = fullResPixel(x, y, f.toFull, f.full.width, f.full.height);
    float cur[4];
    for (int c = 0; c < 4; ++c)
        cur[c] = f.recon[c].at(x, y);
    const float curCount = f.recon[kReconCount].at(x, y);
    Accumulated a{{cur[0], cur[1], cur[2], cur[3]}, curCount, 0.0f, false};
    if (!f.hasHistory() || !ref.valid)
        return a;
    const HistoryTap tap = pickHistoryTexel(f, x, y, traced.x, traced.y, ref);
    if (tap.count <= 0.0f)
        return a;
    const float wHist = historyWeight(f, ref, tap.x, tap.y);
    if (wHist <= 0.0f)
        return a;
    float mean[4], sigma[4], h[4];
    neighbourhoodStats(f, ref, x, y, mean, sigma);
    for (int c = 0; c < 4; ++c)  // history channels 0–3 are R G B AO, like the signal's
        h[c] = std::clamp(f.hist[c].at(tap.x, tap.y), mean[c] - kClampSigma * sigma[c],
                          mean[c] + kClampSigma * sigma[c]);
    // Only the AO (miss) channel drives rejection for SSGI (step 5).
    const float rejection = std::fabs(h[3] - f.hist[kAO].at(tap.x, tap.y));
    const float hCount = std::max(tap.count * wHist * saturate(1.0f - rejection), 0.1f);
    const float wPrev = std::max(0.0f, std::min(hCount, kTargetSamples - curCount));
    for (int c = 0; c < 4; ++c)
        a.value[c] = (h[c] * wPrev + cur[c] * curCount) / (wPrev + curCount);
    a.count = wPrev + curCount;
    a.kept = wPrev / tap.count;
    a.reused = true;
    return a;
}

// The outputs of one trace pixel and, when accumulating, the state next frame's accumulation
// reads: the signal, its capped sample count and the surface (depth, normal) its bilateral
// validation compares with. Returns whether the history contributed.
FP_HD inline bool denoisePixel(const Frame& f, int x, int y) {
    const Accumulated a = accumulatePixel(f, x, y);
    for (int c = 0; c < 3; ++c)
        f.outColor[c].at(x, y) = a.value[c];
    f.outAo.at(x, y) = a.value[3];
    if (f.validity)
        f.validity.at(x, y) = std::min(a.kept, 1.0f);
    if (!f.temporal)
        return a.reused;
    const Surface& ref = f.surfaces.at(x, y);
    for (int c = 0; c < 4; ++c)
        f.state[c].at(x, y) = a.value[c];
    f.state[kCount].at(x, y) = ref.valid ? std::min(a.count, float(kHistoryCap)) : 0.0f;
    const PixelCoord traced = fullResPixel(x, y, f.toFull, f.full.width, f.full.height);
    f.state[kViewDepth].at(x, y) = f.depth.at(traced.x, traced.y);
    f.state[kNX].at(x, y) = ref.normal.x;
    f.state[kNY].at(x, y) = ref.normal.y;
    f.state[kNZ].at(x, y) = ref.normal.z;
    return a.reused;
}

/// The whole pass on either backend (PerPixel.h). `denoiser` 0 passes the raw trace through.
template <class Ports, class Pixels>
void run(PassContext& ctx,
         const Ports& ports,
         const Pixels& pixels,
         int denoiser,
         bool temporalAccumulation,
         bool halfRes) {
    const FrameInfo& frame = ctx.frame();
    const auto& inColor = ports.input(kDiffuse)->image();
    const auto& inAo = ports.input(kAo)->image();
    const auto& depth = ports.input(gbuffer::kDepth)->image();
    const auto& normal = ports.input(gbuffer::kNormal)->image();
    const auto& shadingModel = ports.input(gbuffer::kShadingModel)->image();
    const Extent full{depth.width(), depth.height()};
    const Extent trace = traceExtent(full, halfRes);
    FP_CHECK(inColor.width() == trace.width && inColor.height() == trace.height,
             "diffuse is {}×{} but the trace resolution is {}×{} (ssgi_denoise.halfRes must match "
             "ssgi.halfRes)",
             inColor.width(), inColor.height(), trace.width, trace.height);

    Frame f{};
    f.cam = frame.camera.current;
    f.full = full;
    f.toFull = halfRes ? 2 : 1;
    f.frameMod8 = ue::frameIndexMod8(frame.number);
    f.depth = viewOf(depth.plane(0));
    f.ao = viewOf(inAo.plane(0));
    for (int c = 0; c < 3; ++c)
        f.color[c] = viewOf(inColor.plane(c));
    f.velocity = velocityViewOf(ports.input(gbuffer::kVelocity));
    auto& outColor = ports.overwrite(kDiffuse, {trace});
    auto& outAo = ports.overwrite(kAo, {trace});
    for (int c = 0; c < 3; ++c)
        f.outColor[c] = spanOf(outColor.image().plane(c));
    f.outAo = spanOf(outAo.image().plane(0));
    if (auto* validity = ports.outputIfRequested(kHistoryValidity, {trace}))
        f.validity = spanOf(validity->image().plane(0));

    if (denoiser == 0) {  // r.DiffuseIndirect.Denoiser=0: the raw trace goes through
        pixels.template forEach<0>(
            trace.width, trace.height,
            [=] FP_HD(int x, int y, WorkCounts<0>&) {
                for (int c = 0; c < 3; ++c)
                    f.outColor[c].at(x, y) = f.color[c].at(x, y);
                f.outAo.at(x, y) = f.ao.at(x, y);
            },
            "ssgi_denoise");
        return;
    }

    f.gbuffer = {f.depth,
                 {viewOf(normal.plane(0)), viewOf(normal.plane(1)), viewOf(normal.plane(2))},
                 viewOf(shadingModel.plane(0))};
    const auto surfaceMemory =
        ports.template scratchArray<Surface>(std::size_t(trace.width) * trace.height);
    f.surfaces = {surfaceMemory.get(), trace.width, trace.height, f.toFull};
    f.kernel = kernelTable();
    auto recon = ports.scratch({trace}, {"R", "G", "B", "AO", "N"});
    for (int c = 0; c < kReconChannels; ++c)
        f.recon[c] = spanOf(recon.image().plane(c));

    f.temporal = temporalAccumulation;
    const auto* past = temporalAccumulation ? ports.historyState() : nullptr;
    if (past && past->image().width() == trace.width && past->image().height() == trace.height) {
        for (int c = 0; c < kHistoryChannels; ++c)
            f.hist[c] = viewOf(past->image().plane(c));
        f.prevCam = ctx.history()->camera;
    }
    using StateTexture = std::decay_t<decltype(recon)>;
    StateTexture state;
    if (f.temporal) {
        state = ports.scratch({trace}, historyChannels());
        for (int c = 0; c < kHistoryChannels; ++c)
            f.state[c] = spanOf(state.image().plane(c));
    }

    pixels.template forEach<0>(
        trace.width, trace.height,
        [=] FP_HD(int x, int y, WorkCounts<0>&) {
            f.surfaces.build(f.cam, f.gbuffer, NormalRead::Normalised, x, y);
        },
        "ssgi_denoise surfaces");
    const auto reconstructed = pixels.template forEach<2>(
        trace.width, trace.height,
        [=] FP_HD(int x, int y, WorkCounts<2>& n) { ++n.value[reconstructPixel(f, x, y) ? 0 : 1]; },
        "ssgi_denoise reconstruction");
    const auto reused = pixels.template forEach<1>(
        trace.width, trace.height,
        [=] FP_HD(int x, int y, WorkCounts<1>& n) { n.value[0] += denoisePixel(f, x, y); },
        "ssgi_denoise accumulation");
    ctx.addWork("pixels", reconstructed[0]);
    ctx.addWork("skippedPixels", reconstructed[1]);
    ctx.addWork("historyPixels", reused[0]);
    if (f.temporal)
        ports.keepHistory(std::move(state));
}

/// What run() allocates on the CPU at the trace extent: the surfaces, the reconstruction and, when
/// accumulating, the new state (and the history kept); nothing with the denoiser off.
inline PassMemory memoryOf(Extent trace, int denoiser, bool temporalAccumulation) {
    if (denoiser == 0) return {};
    const std::size_t state = temporalAccumulation ? imageBytes(trace, kHistoryChannels) : 0;
    return {sizeof(Surface) * std::size_t(trace.width) * std::size_t(trace.height) +
                imageBytes(trace, kReconChannels) + state,
            state};
}

}  // namespace fp::ssgi_denoise
