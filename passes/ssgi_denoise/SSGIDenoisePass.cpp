#include "passes/ssgi_denoise/SSGIDenoisePass.h"

#include "passes/common/Bilateral.h"
#include "passes/common/GBuffer.h"
#include "passes/common/Reprojection.h"
#include "passes/common/Surface.h"
#include "passes/core/Error.h"
#include "passes/core/FloatToInt.h"
#include "passes/core/Tiles.h"
#include "passes/core/UnrealRandom.h"
#include "passes/ssgi/SSGIPass.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {
constexpr const char* kDiffuse = "diffuse";
constexpr const char* kAo = "ao";
constexpr const char* kHistoryValidity = "historyValidity";

// reference §6.2: bilateral distance = pixel world radius × 2√2 × 3 (the SSGI multiplier); the
// history test uses the same multiplier (max(3, 3)).
constexpr float kBilateralScale = 2.0f * 1.41421356f * 3.0f;

// History state channels, per trace pixel.
enum HistoryChannel { kR, kG, kB, kAO, kCount, kViewDepth, kNX, kNY, kNZ, kHistoryChannels };
const std::vector<std::string> kHistoryNames = {"R", "G", "B", "AO", "N", "D", "NX", "NY", "NZ"};

// One of the four bilinear texels (00, 10, 01, 11), chosen with probability equal to its weight.
int pickTexel(const float w[4], float u) {
    float acc = 0.0f;
    for (int i = 0; i < 3; ++i)
        if (u < (acc += w[i]))
            return i;
    return 3;
}

// Reconstruction (reference §6.2): the centre and the 8 taps of its track, bilaterally weighted
// against the centre's surface with the smaller of the two pixel radii (MIN_METADATA), summed as
// moment-1 sums. Writes R G B AO (normalised) and the accumulated sample count; false when the
// pixel has no surface and passes through as it is.
bool reconstructPixel(const SurfaceGrid& surfaces,
                      const Image& color,
                      const Plane& ao,
                      int x,
                      int y,
                      Image& recon) {
    using Offset = SSGIDenoisePass::Offset;
    const int TW = color.width(), TH = color.height();
    const Surface& ref = surfaces.at(x, y);
    if (!ref.valid) {
        for (int c = 0; c < 3; ++c)
            recon.plane(c).at(x, y) = color.plane(c).at(x, y);
        recon.plane(3).at(x, y) = ao.at(x, y);
        return false;
    }
    float sum[4] = {color.plane(0).at(x, y), color.plane(1).at(x, y), color.plane(2).at(x, y),
                    ao.at(x, y)};
    float weight = 1.0f;  // the centre sample
    const auto& track = SSGIDenoisePass::kernel()[(x & 1) + 2 * (y & 1)];
    const float qx = float(x & ~1) + 0.5f, qy = float(y & ~1) + 0.5f;
    for (const Offset& o : track) {
        const int nx = int(qx + o.x), ny = int(qy + o.y);
        if (nx < 0 || ny < 0 || nx >= TW || ny >= TH)
            continue;
        const Surface& s = surfaces.at(nx, ny);
        if (!s.valid)
            continue;
        const float w = bilateralWeight(ref, s, std::min(ref.radius, s.radius) * kBilateralScale);
        if (w <= 0.0f)
            continue;
        for (int c = 0; c < 3; ++c)
            sum[c] += w * color.plane(c).at(nx, ny);
        sum[3] += w * ao.at(nx, ny);
        weight += w;
    }
    for (int c = 0; c < 4; ++c)
        recon.plane(c).at(x, y) = sum[c] / weight;
    recon.plane(4).at(x, y) = weight;
    return true;
}

// What the temporal accumulation reads for every trace pixel.
struct TemporalInputs {
    const CameraView& cam;
    const SurfaceGrid& surfaces;
    const Image& recon;  // R G B AO N of this frame's reconstruction
    const Plane& depth;
    const Texture* velocity;
    const PassHistory* past;  // nullptr: no usable history
    const Image* hist;        // past's state, when its size matches the trace
    Extent full;
    int toFull;
    uint32_t frameMod8;
};

// The history texel a pixel reads and its stored sample count (0: off screen or empty).
struct HistoryTap {
    int x, y;
    float count;
};

// Reference §6.2 steps 1–3: reproject, then one texel of the bilinear 2×2 footprint picked by IGN.
HistoryTap pickHistoryTexel(const TemporalInputs& in,
                            int x,
                            int y,
                            int px,
                            int py,
                            const Surface& ref) {
    const int TW = in.recon.width(), TH = in.recon.height();
    const Vec3d p{ref.position.x, ref.position.y, ref.position.z};
    const PreviousPixel prev =
        reprojectPixel(px, py, p, in.cam.position, in.velocity, in.past->camera);
    const double tu = prev.u / in.toFull - 0.5, tv = prev.v / in.toFull - 0.5;
    // Far off screen (or NaN) only the clamped edge texel is read, and then with no weight.
    const int x0 = floorToInt(tu, -2, TW + 1), y0 = floorToInt(tv, -2, TH + 1);
    const float fx = std::isfinite(tu) ? std::clamp(float(tu - x0), 0.0f, 1.0f) : 0.0f;
    const float fy = std::isfinite(tv) ? std::clamp(float(tv - y0), 0.0f, 1.0f) : 0.0f;
    const float u = ue::interleavedGradientNoise(float(x) + 0.5f, float(y) + 0.5f, in.frameMod8);
    const float w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    const int pick = pickTexel(w, u);
    const int hx = x0 + (pick & 1), hy = y0 + (pick >> 1);
    const int cx = std::clamp(hx, 0, TW - 1), cy = std::clamp(hy, 0, TH - 1);
    return {cx, cy, prev.onScreen(in.full) ? in.hist->plane(kCount).at(cx, cy) : 0.0f};
}

// Bilateral validation of the history texel against its own surface (reference §6.2 step 3,
// history multiplier max(3, 3) = 3), rebuilt from the depth and normal the history kept.
float historyWeight(const TemporalInputs& in, const Surface& ref, int cx, int cy) {
    const Image& hist = *in.hist;
    const CameraView& prevCam = in.past->camera;
    const double hd = hist.plane(kViewDepth).at(cx, cy);
    const Vec3d hp = prevCam.translatedFromPixel(std::min(cx * in.toFull, in.full.width - 1),
                                                 std::min(cy * in.toFull, in.full.height - 1), hd) +
                     (prevCam.position - in.cam.position);
    const Vec3f hn{hist.plane(kNX).at(cx, cy), hist.plane(kNY).at(cx, cy),
                   hist.plane(kNZ).at(cx, cy)};
    return bilateralWeight(ref, {float(hp.x), float(hp.y), float(hp.z)}, hn,
                           ref.radius * kBilateralScale);
}

// Reference §6.2 step 4: mean and σ of the current reconstruction on the "plus" set (centre + 4
// edge neighbours), bilaterally weighted with the centre's own radius.
void neighbourhoodStats(const TemporalInputs& in,
                        const Surface& ref,
                        int x,
                        int y,
                        float mean[4],
                        float sigma[4]) {
    const int TW = in.recon.width(), TH = in.recon.height();
    float m1[4] = {0, 0, 0, 0}, m2[4] = {0, 0, 0, 0}, wSum = 0.0f;
    static constexpr int kPlus[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& o : kPlus) {
        const int nx = x + o[0], ny = y + o[1];
        if (nx < 0 || ny < 0 || nx >= TW || ny >= TH)
            continue;
        const Surface& s = in.surfaces.at(nx, ny);
        if (!s.valid)
            continue;
        const float w =
            (o[0] == 0 && o[1] == 0) ? 1.0f : bilateralWeight(ref, s, ref.radius * kBilateralScale);
        for (int c = 0; c < 4; ++c) {
            const float v = in.recon.plane(c).at(nx, ny);
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

// Reference §6.2 steps 1–6 for one pixel: the reconstruction alone when there is no valid history,
// else the clamped history blended with it by sample counts.
Accumulated accumulatePixel(const TemporalInputs& in, int x, int y) {
    using P = SSGIDenoisePass;
    const Surface& ref = in.surfaces.at(x, y);
    const int px = std::min(x * in.toFull, in.full.width - 1);  // the full-res pixel traced
    const int py = std::min(y * in.toFull, in.full.height - 1);
    float cur[4];
    for (int c = 0; c < 4; ++c)
        cur[c] = in.recon.plane(c).at(x, y);
    const float curCount = in.recon.plane(4).at(x, y);
    Accumulated a{{cur[0], cur[1], cur[2], cur[3]}, curCount, 0.0f, false};
    if (!in.hist || !ref.valid)
        return a;
    const HistoryTap tap = pickHistoryTexel(in, x, y, px, py, ref);
    if (tap.count <= 0.0f)
        return a;
    const float wHist = historyWeight(in, ref, tap.x, tap.y);
    if (wHist <= 0.0f)
        return a;
    float mean[4], sigma[4], h[4];
    neighbourhoodStats(in, ref, x, y, mean, sigma);
    for (int c = 0; c < 4; ++c)  // history channels 0–3 are R G B AO, like the signal's
        h[c] = std::clamp(in.hist->plane(c).at(tap.x, tap.y), mean[c] - P::kClampSigma * sigma[c],
                          mean[c] + P::kClampSigma * sigma[c]);
    // Only the AO (miss) channel drives rejection for SSGI (step 5).
    const float rejection = std::fabs(h[3] - in.hist->plane(kAO).at(tap.x, tap.y));
    const float hCount = std::max(tap.count * wHist * saturate(1.0f - rejection), 0.1f);
    const float wPrev = std::max(0.0f, std::min(hCount, P::kTargetSamples - curCount));
    for (int c = 0; c < 4; ++c)
        a.value[c] = (h[c] * wPrev + cur[c] * curCount) / (wPrev + curCount);
    a.count = wPrev + curCount;
    a.kept = wPrev / tap.count;
    a.reused = true;
    return a;
}

// The state next frame's accumulation reads: the signal, its capped sample count and the
// surface (depth, normal) its bilateral validation compares with.
void storeHistory(const TemporalInputs& in, const Accumulated& a, int x, int y, Image& state) {
    const Surface& ref = in.surfaces.at(x, y);
    for (int c = 0; c < 4; ++c)
        state.plane(c).at(x, y) = a.value[c];
    state.plane(kCount).at(x, y) =
        ref.valid ? std::min(a.count, SSGIDenoisePass::kHistoryCap) : 0.0f;
    state.plane(kViewDepth).at(x, y) = in.depth.at(std::min(x * in.toFull, in.full.width - 1),
                                                   std::min(y * in.toFull, in.full.height - 1));
    state.plane(kNX).at(x, y) = ref.normal.x;
    state.plane(kNY).at(x, y) = ref.normal.y;
    state.plane(kNZ).at(x, y) = ref.normal.z;
}

// r.DiffuseIndirect.Denoiser=0: the raw trace, copied row by row.
void copyRows(const Image& color, const Plane& ao, Image& outColor, Plane& outAo) {
    const int W = color.width();
    for (int y = 0; y < color.height(); ++y) {
        for (int c = 0; c < 3; ++c)
            std::copy(color.plane(c).row(y), color.plane(c).row(y) + W, outColor.plane(c).row(y));
        std::copy(ao.row(y), ao.row(y) + W, outAo.row(y));
    }
}

// The spatial stage over the trace grid: R G B AO normalised, and N, the accumulated weight.
Image reconstruct(PassContext& ctx,
                  const SurfaceGrid& surfaces,
                  const Image& color,
                  const Plane& ao) {
    Image recon(color.width(), color.height(), {"R", "G", "B", "AO", "N"});
    forEachTile(color.width(), color.height(), [&](const Tile& t) {
        uint64_t pixels = 0, skipped = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (reconstructPixel(surfaces, color, ao, x, y, recon))
                    ++pixels;
                else
                    ++skipped;
            }
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", skipped);
    });
    return recon;
}
}  // namespace

ParamSpec<SSGIDenoiseParams> SSGIDenoisePass::paramSpec() {
    ParamSpec<SSGIDenoiseParams> s;
    s.add("denoiser", &Params::denoiser,
          "0 passes the raw trace through; 1 (and 2, a third-party denoiser in Unreal) run "
          "framepass's")
        .range(0, 2)
        .cvar("r.DiffuseIndirect.Denoiser");
    s.add("temporalAccumulation", &Params::temporalAccumulation, "accumulate across frames")
        .cvar("r.GlobalIllumination.Denoiser.TemporalAccumulation");
    s.add("halfRes", &Params::halfRes,
          "the SSGI trace ran at half resolution: the denoiser runs at the trace resolution (the "
          "same cvars set ssgi.halfRes)")
        .cvar("r.SSGI.HalfRes")
        .cvar("r.DiffuseIndirect.HalfRes");
    return s;
}

const std::array<std::array<SSGIDenoisePass::Offset, SSGIDenoisePass::kTaps>,
                 SSGIDenoisePass::kTracks>&
SSGIDenoisePass::kernel() {
    // Unreal's Stackowiak tables are not transcribed (reference §13.1). framepass builds the same
    // kind of set [inferred]: the pixels of an 8×8 block around the quad centre, quad excluded,
    // ordered by radius then angle and dealt round-robin to the four tracks, so each pixel of the
    // quad sees its own 8 taps, balanced around the centre, out to 2.5·√2 pixels.
    static const auto table = [] {
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
        std::array<std::array<Offset, kTaps>, kTracks> t{};
        for (int i = 0; i < kTracks * kTaps; ++i)
            t[i % kTracks][i / kTracks] = {c[i].x, c[i].y};
        return t;
    }();
    return table;
}

PassIO SSGIDenoisePass::describe() const {
    PassIO io;
    io.inputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "raw SSGI radiance"},
        {.name = kAo, .channels = {"Y"}, .doc = "raw SSGI AO"},
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit (0) pixels are left as they are"),
        gbuffer::velocityInput(
            "optional motion for reprojection; the history's camera is used when unbound"),
    };
    io.outputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "denoised radiance"},
        {.name = kAo, .channels = {"Y"}, .doc = "denoised AO"},
        {.name = kHistoryValidity,
         .channels = {"Y"},
         .doc = "debug: share of last frame's history kept (0 = none: first frame, cut, "
                "disocclusion)"},
    };
    io.needsCamera = true;
    io.temporal = mParams.denoiser > 0 && mParams.temporalAccumulation;
    return io;
}

std::vector<Extent> SSGIDenoisePass::outputExtents(std::string_view, Extent frame) const {
    return {SSGIPass::traceExtent(frame, mParams.halfRes)};
}

void SSGIDenoisePass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const CameraView& cam = frame.camera.current;
    const Image& inColor = ctx.input(kDiffuse)->image();
    const Plane& inAo = ctx.input(kAo)->image().plane(0);
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Image& normal = ctx.input(gbuffer::kNormal)->image();
    const Plane& shadingModel = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const Extent full{depth.width(), depth.height()};
    const Extent trace = SSGIPass::traceExtent(full, mParams.halfRes);
    FP_CHECK(inColor.width() == trace.width && inColor.height() == trace.height,
             "diffuse is {}×{} but the trace resolution is {}×{} (ssgi_denoise.halfRes must match "
             "ssgi.halfRes)",
             inColor.width(), inColor.height(), trace.width, trace.height);
    const int toFull = mParams.halfRes ? 2 : 1;

    Texture& outColor = ctx.output(kDiffuse, {trace});
    Texture& outAo = ctx.output(kAo, {trace});
    Texture* validity =
        ctx.isRequested(kHistoryValidity) ? &ctx.output(kHistoryValidity, {trace}) : nullptr;
    if (mParams.denoiser == 0) {  // r.DiffuseIndirect.Denoiser=0: the raw trace goes through
        copyRows(inColor, inAo, outColor.image(), outAo.image().plane(0));
        return;
    }
    const SurfaceGrid surfaces(cam, {depth, normal, shadingModel}, trace, toFull,
                               NormalRead::Normalised);
    const Image recon = reconstruct(ctx, surfaces, inColor, inAo);

    const bool temporal = mParams.temporalAccumulation;
    const PassHistory* past = temporal ? ctx.history() : nullptr;
    const Image* hist = past && past->state.image().width() == trace.width &&
                                past->state.image().height() == trace.height
                            ? &past->state.image()
                            : nullptr;
    const TemporalInputs in{cam,  surfaces, recon, depth,  ctx.input(gbuffer::kVelocity),
                            past, hist,     full,  toFull, ue::frameIndexMod8(frame.number)};
    Image state;
    if (temporal)
        state = Image(trace.width, trace.height, kHistoryNames);
    forEachTile(trace.width, trace.height, [&](const Tile& t) {
        uint64_t reused = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const Accumulated a = accumulatePixel(in, x, y);
                reused += a.reused;
                for (int c = 0; c < 3; ++c)
                    outColor.image().plane(c).at(x, y) = a.value[c];
                outAo.image().plane(0).at(x, y) = a.value[3];
                if (validity)
                    validity->image().plane(0).at(x, y) = std::min(a.kept, 1.0f);
                if (temporal)
                    storeHistory(in, a, x, y, state);
            }
        ctx.addWork("historyPixels", reused);
    });
    if (temporal)
        ctx.keepHistory(Texture(std::move(state)));
}

}  // namespace fp
