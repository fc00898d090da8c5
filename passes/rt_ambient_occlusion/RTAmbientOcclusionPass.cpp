#include "passes/rt_ambient_occlusion/RTAmbientOcclusionPass.h"

#include "foundation/RayScene.h"
#include "foundation/PerPixel.h"
#include "foundation/Tiles.h"
#include "framework/PassPorts.h"
#include "passes/rt_ambient_occlusion/AmbientOcclusionLanes.h"
#include "passes/rt_ambient_occlusion/RTAmbientOcclusionKernel.h"
#include "screenspace/GBuffer.h"

#include <algorithm>
#include <vector>

namespace fp {

namespace {

constexpr uint32_t kSeed = 0x5254414Fu;    // "RTAO"

// A tile's rays in flight, as structure-of-arrays, each with its pixel and weight: a few hundred
// at a time, so they stay in the core's cache between being drawn, traced and summed.
class RayBatch {
public:
    static constexpr int kFlushAt = 256;  // rays drawn before the full packets among them go
    static constexpr int kCapacity = kFlushAt + kMaxPacketSize;  // checked after every ray

    int size() const { return mCount; }
    /// Entry k of a row's rays, for pixel `pixel`.
    void push(const rtao::RowRays& r, int k, float length, int pixel) {
        const int i = mCount++;
        mOx[i] = r.ox[k], mOy[i] = r.oy[k], mOz[i] = r.oz[k];
        mDx[i] = r.dx[k], mDy[i] = r.dy[k], mDz[i] = r.dz[k];
        mTfar[i] = length, mWeight[i] = r.weight[k], mPixel[i] = pixel;
    }
    /// Traces the first `count` rays in packets of `width` (the last may be partial) and adds
    /// each to its pixel's sums in the order drawn; the rays after them move to the front.
    void trace(const RayScene& rs, int count, int width, bool wantDistance,
               const rtao::FrameSetup& s, rtao::Sums* sums) {
        const RayArrays all{mOx, mOy, mOz, mDx, mDy, mDz, mTfar};
        for (int first = 0; first < count; first += width) {
            const int n = std::min(width, count - first);
            bool blocked[kMaxPacketSize];
            float hitT[kMaxPacketSize];
            rs.occludedWithDistancePacket(all.from(first), n, width, blocked,
                                          wantDistance ? hitT : nullptr);
            for (int k = 0; k < n; ++k)
                sums[mPixel[first + k]].add(s, mWeight[first + k], blocked[k],
                                            wantDistance ? hitT[k] : -1.0f);
        }
        const int rest = mCount - count;
        for (float* a : {mOx, mOy, mOz, mDx, mDy, mDz, mTfar, mWeight})
            std::copy(a + count, a + mCount, a);
        std::copy(mPixel + count, mPixel + mCount, mPixel);
        mCount = rest;
    }

private:
    int mCount = 0;
    float mOx[kCapacity], mOy[kCapacity], mOz[kCapacity], mDx[kCapacity], mDy[kCapacity],
        mDz[kCapacity], mTfar[kCapacity], mWeight[kCapacity];
    int mPixel[kCapacity];
};

// The scalar reference of rtao::setupRow: rtao::setupPixel one pixel at a time.
void setupRowScalar(const rtao::FrameSetup& s, const rtao::RowInputs& in, rtao::RowPixels& out) {
    out.count = in.count;
    for (int i = 0; i < in.count; ++i) {
        rtao::Pixel p;
        out.active[i] = rtao::setupPixel(s, in.depth, in.model, in.normal, in.x0 + i, in.y, p);
        if (!out.active[i]) continue;
        out.px[i] = p.p.x, out.py[i] = p.p.y, out.pz[i] = p.p.z;
        out.sx[i] = p.shading.x, out.sy[i] = p.shading.y, out.sz[i] = p.shading.z;
        out.gx[i] = p.geometric.x, out.gy[i] = p.geometric.y, out.gz[i] = p.geometric.z;
        out.tx[i] = p.tangent.x, out.ty[i] = p.tangent.y, out.tz[i] = p.tangent.z;
        out.bx[i] = p.bitangent.x, out.by[i] = p.bitangent.y, out.bz[i] = p.bitangent.z;
        out.ex[i] = p.toEye.x, out.ey[i] = p.toEye.y, out.ez[i] = p.toEye.z;
        out.eyeDistance[i] = p.eyeDistance;
        out.overlap[i] = p.shadingDotGeometric;
        out.rng[i] = p.rng;
    }
}

// The scalar reference of rtao::sampleRow: rtao::sampleRay one active pixel at a time.
void sampleRowScalar(const rtao::FrameSetup& s, rtao::RowPixels& px, rtao::RowRays& rays) {
    for (int i = 0; i < px.count; ++i) {
        if (!px.active[i]) continue;
        rtao::Pixel p{{px.px[i], px.py[i], px.pz[i]}, {px.sx[i], px.sy[i], px.sz[i]},
                      {px.gx[i], px.gy[i], px.gz[i]}, {px.tx[i], px.ty[i], px.tz[i]},
                      {px.bx[i], px.by[i], px.bz[i]}, {px.ex[i], px.ey[i], px.ez[i]},
                      px.eyeDistance[i], px.overlap[i], px.rng[i]};
        const rtao::AoRay r = rtao::sampleRay(s, p);
        px.rng[i] = p.rng;
        rays.ox[i] = r.org.x, rays.oy[i] = r.org.y, rays.oz[i] = r.org.z;
        rays.dx[i] = r.dir.x, rays.dy[i] = r.dir.y, rays.dz[i] = r.dir.z;
        rays.weight[i] = r.weight;
    }
}

}  // namespace

ParamSpec<RTAmbientOcclusionParams> RTAmbientOcclusionPass::paramSpec() {
    ParamSpec<RTAmbientOcclusionParams> s;
    s.add("samplesPerPixel", &Params::samplesPerPixel,
          "AO rays per pixel; −1 = the post-process volume's RayTracingAOSamplesPerPixel (1)")
        .range(-1, 64)
        .cvar("r.RayTracing.AmbientOcclusion.SamplesPerPixel");
    s.add("intensity", &Params::intensity,
          "post-process RayTracingAOIntensity: a blocked ray counts 1 − intensity (0: the pass "
          "traces nothing and writes 1, as Unreal skips it)")
        .range(0.0, 1.0);
    s.add("radius", &Params::radius,
          "post-process RayTracingAORadius, cm: a hit closer than this occludes the ray")
        .range(0.0, 1e7);
    s.add("normalBias", &Params::normalBias, "largest normal/camera bias, cm (at N·L = 0)")
        .range(0.01, 1e6)
        .cvar("r.RayTracing.NormalBias");
    s.add("lanes", &Params::lanes,
          "Embree's path: set up pixels and draw their rays in SIMD lanes (false: the scalar "
          "reference, one pixel at a time; same result bit for bit)");
    s.add("traversal", &Params::traversal,
          "\"embree\": Embree's packets; \"bvh\": framepass's own BVH one pixel at a time, the "
          "code the GPU runs (on the GPU the pass always traverses it)")
        .choices({"embree", "bvh"});
    return s;
}

PassIO RTAmbientOcclusionPass::describe() const {
    PassIO io;
    io.roles.unrealSwitch = "r.RayTracing.AmbientOcclusion=1";
    io.roles.tracesRays = true;  // bench replays its rays in a bare Embree loop
    io.inputs = {
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit and sky pixels are skipped"),
    };
    io.outputs = {
        {.name = rtao::kAo,
         .channels = {"Y"},
         .doc = "ambient occlusion, 1 open: weighted fraction of rays unblocked within the radius, "
                "× the shading normal's lobe overlap with the geometric normal's"},
        {.name = rtao::kHitDistance,
         .channels = {"Y"},
         .doc = "closest hit over the samples, scene units; 10000 cm where none hit; −2 sky and "
                "unlit"},
    };
    io.needsCamera = true;
    io.needsScene = true;
    io.workUnit = "rays";
    return io;
}

rtao::FrameSetup RTAmbientOcclusionPass::frameSetup(PassContext& ctx) const {
    const RayScene& rs = ctx.scene();
    const CameraView& cam = ctx.frame().camera.current;
    const float cm = float(rs.scene().centimetre());
    rtao::FrameSetup s{};
    s.camera = cam;
    s.eyeOffset = cam.position - rs.origin();
    s.spp = mParams.samplesPerPixel > 0 ? mParams.samplesPerPixel : 1;
    s.radius = mParams.radius * cm;
    s.intensity = mParams.intensity;
    const RayBias bias = RayBias::fromCm(mParams.normalBias, cm);
    s.maxBias = bias.max;
    s.minBias = bias.min;
    s.noHitDistance = rtao::kNoHitCm * cm;
    s.rngKey = Rng::frameKey(ctx.frame().number, kSeed);
    return s;
}

void RTAmbientOcclusionPass::execute(PassContext& ctx) {
    const rtao::FrameSetup s = frameSetup(ctx);
    // At intensity 0 (Unreal runs no RTAO) run() writes the skipped values and traces nothing.
    if (mParams.traversal == "bvh" || s.intensity <= 0.0f) {
        rtao::run(ctx, HostPorts{ctx}, CpuPixels{}, s);
        return;
    }
    const Extent size = ctx.frame().extent;
    Plane& ao = ctx.output(rtao::kAo, {size}).image().plane(0);
    Plane& hitDistance = ctx.output(rtao::kHitDistance, {size}).image().plane(0);
    const int spp = s.spp;
    const RayScene& rs = ctx.scene();
    const PlaneView depth = viewOf(ctx.input(gbuffer::kDepth)->image().plane(0));
    const PlaneView model = viewOf(ctx.input(gbuffer::kShadingModel)->image().plane(0));
    const Image& n = ctx.input(gbuffer::kNormal)->image();
    const PlaneView normal[3] = {viewOf(n.plane(0)), viewOf(n.plane(1)), viewOf(n.plane(2))};
    const bool wantDistance = ctx.isRequested(rtao::kHitDistance);

    const int width = rs.packetWidth();
    forEachTile(size.width, size.height, [&](const Tile& t) {
        // A row at a time: each pixel set up and each sample's ray drawn (in SIMD lanes, or one
        // pixel at a time as the scalar reference), the rays batched across pixels and traced in
        // full packets; every pixel draws its own stream and its rays add to its sums in the order
        // drawn, so the result is that of one ray at a time.
        const int w = t.x1 - t.x0, count = w * (t.y1 - t.y0);
        std::vector<float> overlap(count, -1.0f);  // the lobe overlap; −1: a skipped pixel
        std::vector<rtao::Sums> sums(count);
        RayBatch batch;
        rtao::RowPixels row;
        rtao::RowRays rowRays;
        uint64_t rays = 0;
        for (int y = t.y0; y < t.y1; ++y) {
            const rtao::RowInputs in{.x0 = t.x0, .y = y, .count = w, .depth = depth, .model = model,
                                     .normal = {normal[0], normal[1], normal[2]}};
            if (mParams.lanes)
                rtao::setupRow(s, in, row);
            else
                setupRowScalar(s, in, row);
            const int first = (y - t.y0) * w;
            for (int i = 0; i < w; ++i)
                if (row.active[i]) overlap[first + i] = row.overlap[i];
            for (int k = 0; k < spp; ++k) {
                if (mParams.lanes)
                    rtao::sampleRow(s, row, rowRays);
                else
                    sampleRowScalar(s, row, rowRays);
                for (int i = 0; i < w; ++i) {
                    if (!row.active[i]) continue;
                    batch.push(rowRays, i, s.radius, first + i);
                    ++rays;
                    if (batch.size() >= RayBatch::kFlushAt)
                        batch.trace(rs, batch.size() - batch.size() % width, width, wantDistance, s,
                                    sums.data());
                }
            }
        }
        batch.trace(rs, batch.size(), width, wantDistance, s, sums.data());
        uint64_t skipped = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const int i = (y - t.y0) * w + (x - t.x0);
                if (overlap[i] < 0.0f) {
                    ao.at(x, y) = 1.0f;
                    hitDistance.at(x, y) = rtao::kSkippedHitDistance;
                    ++skipped;
                    continue;
                }
                const rtao::Resolved r = rtao::resolve(s, overlap[i], sums[i]);
                ao.at(x, y) = r.ao;
                hitDistance.at(x, y) = r.hitDistance;
            }
        ctx.addWork("rays", rays);
        ctx.addWork("pixels", uint64_t(count) - skipped);
        ctx.addWork("skippedPixels", skipped);
    });
}

}  // namespace fp
