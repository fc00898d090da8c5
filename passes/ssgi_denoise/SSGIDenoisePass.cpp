#include "passes/ssgi_denoise/SSGIDenoisePass.h"

#include "passes/core/Error.h"
#include "passes/core/ShadingModel.h"
#include "passes/core/Tiles.h"
#include "passes/core/UnrealRandom.h"
#include "passes/ssgi/SSGIPass.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {
constexpr const char* kDiffuse = "diffuse";
constexpr const char* kAo = "ao";
constexpr const char* kDepth = "depth";
constexpr const char* kNormal = "normal";
constexpr const char* kShadingModel = "shadingModel";
constexpr const char* kVelocity = "velocity";
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

// What the bilateral weights need of one trace pixel.
struct Surface {
    bool valid = false;
    Vec3f position;    // camera-relative, scene units
    Vec3f normal;      // world, unit
    float radius = 0;  // pixel world radius at the trace resolution
};

// reference §6.2: W = saturate(1 − |N_ref·(P − P_ref)|/D) × max(N_ref·N, 0)⁴.
float bilateral(const Surface& ref, const Vec3f& p, const Vec3f& n, float distance) {
    const float plane = std::fabs(dot(ref.normal, p - ref.position));
    const float wPos = saturate(1.0f - plane / distance);
    const float c = std::max(dot(ref.normal, n), 0.0f);
    return wPos * (c * c) * (c * c);
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
         .doc = "unlit (0) pixels are left as they are"},
        {.name = kVelocity,
         .channels = {"X", "Y"},
         .optional = true,
         .doc = "optional motion for reprojection; the history's camera is used when unbound"},
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
    const Plane& depth = ctx.input(kDepth)->image().plane(0);
    const Image& normal = ctx.input(kNormal)->image();
    const Plane& shadingModel = ctx.input(kShadingModel)->image().plane(0);
    const Texture* velocity = ctx.input(kVelocity);
    const Extent full{depth.width(), depth.height()};
    const Extent trace = SSGIPass::traceExtent(full, mParams.halfRes);
    FP_CHECK(inColor.width() == trace.width && inColor.height() == trace.height,
             "diffuse is {}×{} but the trace resolution is {}×{} (ssgi_denoise.halfRes must match "
             "ssgi.halfRes)",
             inColor.width(), inColor.height(), trace.width, trace.height);
    const int toFull = mParams.halfRes ? 2 : 1;
    const int TW = trace.width, TH = trace.height;

    Texture& outColor = ctx.output(kDiffuse, {trace});
    Texture& outAo = ctx.output(kAo, {trace});
    Texture* validity =
        ctx.isRequested(kHistoryValidity) ? &ctx.output(kHistoryValidity, {trace}) : nullptr;

    if (mParams.denoiser == 0) {  // r.DiffuseIndirect.Denoiser=0: the raw trace goes through
        for (int y = 0; y < TH; ++y) {
            for (int c = 0; c < 3; ++c)
                std::copy(inColor.plane(c).row(y), inColor.plane(c).row(y) + TW,
                          outColor.image().plane(c).row(y));
            std::copy(inAo.row(y), inAo.row(y) + TW, outAo.image().plane(0).row(y));
        }
        return;
    }

    // --- per trace pixel: the surface the bilateral weights compare ---------------------------
    std::vector<Surface> surfaces(std::size_t(TW) * TH);
    auto surfaceAt = [&](int x, int y) -> const Surface& {
        return surfaces[std::size_t(y) * TW + x];
    };
    forEachTile(TW, TH, [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const int px = std::min(x * toFull, full.width - 1);
                const int py = std::min(y * toFull, full.height - 1);
                const double d = depth.at(px, py);
                Surface& s = surfaces[std::size_t(y) * TW + x];
                if (!isLitSurface(d, shadingModel.at(px, py)))
                    continue;
                const Vec3d p = cam.translatedFromPixel(px, py, d);
                s.valid = true;
                s.position = {float(p.x), float(p.y), float(p.z)};
                s.normal = normalize(Vec3f{normal.plane(0).at(px, py), normal.plane(1).at(px, py),
                                           normal.plane(2).at(px, py)});
                s.radius = float(cam.pixelRadiusAtDepth(d)) * float(toFull);
            }
    });

    // --- reconstruction: centre + 8 bilateral taps (moment-1 sums) ----------------------------
    // Channels: normalised R G B AO and the accumulated sample count.
    Image recon(TW, TH, {"R", "G", "B", "AO", "N"});
    const auto& taps = kernel();
    forEachTile(TW, TH, [&](const Tile& t) {
        uint64_t pixels = 0, skipped = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const Surface& ref = surfaceAt(x, y);
                if (!ref.valid) {
                    for (int c = 0; c < 3; ++c)
                        recon.plane(c).at(x, y) = inColor.plane(c).at(x, y);
                    recon.plane(3).at(x, y) = inAo.at(x, y);
                    ++skipped;
                    continue;
                }
                ++pixels;
                float sum[4] = {inColor.plane(0).at(x, y), inColor.plane(1).at(x, y),
                                inColor.plane(2).at(x, y), inAo.at(x, y)};
                float weight = 1.0f;  // the centre sample
                const auto& track = taps[(x & 1) + 2 * (y & 1)];
                const float qx = float(x & ~1) + 0.5f, qy = float(y & ~1) + 0.5f;
                for (const Offset& o : track) {
                    const int nx = int(qx + o.x), ny = int(qy + o.y);
                    if (nx < 0 || ny < 0 || nx >= TW || ny >= TH)
                        continue;
                    const Surface& s = surfaceAt(nx, ny);
                    if (!s.valid)
                        continue;
                    const float w = bilateral(ref, s.position, s.normal,
                                              std::min(ref.radius, s.radius) * kBilateralScale);
                    if (w <= 0.0f)
                        continue;
                    for (int c = 0; c < 3; ++c)
                        sum[c] += w * inColor.plane(c).at(nx, ny);
                    sum[3] += w * inAo.at(nx, ny);
                    weight += w;
                }
                for (int c = 0; c < 4; ++c)
                    recon.plane(c).at(x, y) = sum[c] / weight;
                recon.plane(4).at(x, y) = weight;
            }
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", skipped);
    });

    // --- temporal accumulation -----------------------------------------------------------------
    const bool temporal = mParams.temporalAccumulation;
    const PassHistory* past = temporal ? ctx.history() : nullptr;
    const Image* hist =
        past && past->state.image().width() == TW && past->state.image().height() == TH
            ? &past->state.image()
            : nullptr;
    Image state;
    if (temporal)
        state = Image(TW, TH, kHistoryNames);
    const uint32_t frameMod8 = ue::frameIndexMod8(frame.number);

    forEachTile(TW, TH, [&](const Tile& t) {
        uint64_t reused = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const Surface& ref = surfaceAt(x, y);
                const int px = std::min(x * toFull, full.width - 1);  // the full-res pixel traced
                const int py = std::min(y * toFull, full.height - 1);
                float cur[4];
                for (int c = 0; c < 4; ++c)
                    cur[c] = recon.plane(c).at(x, y);
                const float curCount = recon.plane(4).at(x, y);
                float out[4] = {cur[0], cur[1], cur[2], cur[3]};
                float outCount = curCount, kept = 0.0f;

                if (hist && ref.valid) {
                    // Where this surface was in the history's frame (full-res pixels).
                    double pu, pv;
                    if (velocity) {
                        pu = px + 0.5 + velocity->image().plane(0).at(px, py);
                        pv = py + 0.5 + velocity->image().plane(1).at(px, py);
                    } else {
                        const Vec3d p{ref.position.x, ref.position.y, ref.position.z};
                        const auto proj = past->camera.projectOffset(p, cam.position);
                        pu = proj.depth > 0 ? proj.px : -1.0;
                        pv = proj.py;
                    }
                    // Stochastic 2×2 tap: one bilinear texel chosen by IGN (reference §6.2 step 3).
                    const double tu = pu / toFull - 0.5, tv = pv / toFull - 0.5;
                    const int x0 = int(std::floor(tu)), y0 = int(std::floor(tv));
                    const float fx = float(tu - x0), fy = float(tv - y0);
                    const float u =
                        ue::interleavedGradientNoise(float(x) + 0.5f, float(y) + 0.5f, frameMod8);
                    const float w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
                    const int pick = pickTexel(w, u);
                    const int hx = x0 + (pick & 1), hy = y0 + (pick >> 1);
                    const bool onScreen = pu >= 0 && pv >= 0 && pu < full.width && pv < full.height;
                    const int cx = std::clamp(hx, 0, TW - 1), cy = std::clamp(hy, 0, TH - 1);
                    const float histCount = onScreen ? hist->plane(kCount).at(cx, cy) : 0.0f;
                    if (histCount > 0.0f) {
                        // Bilateral validation against the history's own surface.
                        const double hd = hist->plane(kViewDepth).at(cx, cy);
                        const Vec3d hp = past->camera.translatedFromPixel(
                                             std::min(cx * toFull, full.width - 1),
                                             std::min(cy * toFull, full.height - 1), hd) +
                                         (past->camera.position - cam.position);
                        const Vec3f hn{hist->plane(kNX).at(cx, cy), hist->plane(kNY).at(cx, cy),
                                       hist->plane(kNZ).at(cx, cy)};
                        const float wHist = bilateral(ref, {float(hp.x), float(hp.y), float(hp.z)},
                                                      hn, ref.radius * kBilateralScale);
                        if (wHist > 0.0f) {
                            // Neighbourhood of the current signal: centre + 4 edge neighbours.
                            float m1[4] = {0, 0, 0, 0}, m2[4] = {0, 0, 0, 0}, wSum = 0.0f;
                            static constexpr int kPlus[5][2] = {
                                {0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
                            for (const auto& o : kPlus) {
                                const int nx = x + o[0], ny = y + o[1];
                                if (nx < 0 || ny < 0 || nx >= TW || ny >= TH)
                                    continue;
                                const Surface& s = surfaceAt(nx, ny);
                                if (!s.valid)
                                    continue;
                                const float w = (o[0] == 0 && o[1] == 0)
                                                    ? 1.0f
                                                    : bilateral(ref, s.position, s.normal,
                                                                ref.radius * kBilateralScale);
                                for (int c = 0; c < 4; ++c) {
                                    const float v = recon.plane(c).at(nx, ny);
                                    m1[c] += w * v;
                                    m2[c] += w * v * v;
                                }
                                wSum += w;
                            }
                            float h[4];
                            for (int c = 0; c < 4; ++c) {
                                const float mean = m1[c] / wSum;
                                const float sigma =
                                    std::sqrt(std::fabs(m2[c] / wSum - mean * mean));
                                // History channels 0–3 are R G B AO, like the signal's.
                                h[c] = std::clamp(hist->plane(c).at(cx, cy),
                                                  mean - kClampSigma * sigma,
                                                  mean + kClampSigma * sigma);
                            }
                            // Only the AO (miss) channel drives rejection for SSGI (step 5).
                            const float rejection = std::fabs(h[3] - hist->plane(kAO).at(cx, cy));
                            const float hCount =
                                std::max(histCount * wHist * saturate(1.0f - rejection), 0.1f);
                            const float wPrev =
                                std::max(0.0f, std::min(hCount, kTargetSamples - curCount));
                            for (int c = 0; c < 4; ++c)
                                out[c] = (h[c] * wPrev + cur[c] * curCount) / (wPrev + curCount);
                            outCount = wPrev + curCount;
                            kept = wPrev / histCount;
                            ++reused;
                        }
                    }
                }
                for (int c = 0; c < 3; ++c)
                    outColor.image().plane(c).at(x, y) = out[c];
                outAo.image().plane(0).at(x, y) = out[3];
                if (validity)
                    validity->image().plane(0).at(x, y) = std::min(kept, 1.0f);
                if (temporal) {
                    for (int c = 0; c < 4; ++c)
                        state.plane(c).at(x, y) = out[c];
                    state.plane(kCount).at(x, y) =
                        ref.valid ? std::min(outCount, kHistoryCap) : 0.0f;
                    state.plane(kViewDepth).at(x, y) = depth.at(px, py);
                    state.plane(kNX).at(x, y) = ref.normal.x;
                    state.plane(kNY).at(x, y) = ref.normal.y;
                    state.plane(kNZ).at(x, y) = ref.normal.z;
                }
            }
        ctx.addWork("historyPixels", reused);
    });
    if (temporal)
        ctx.keepHistory(Texture(std::move(state)));
}

}  // namespace fp
