// RTGlobalIlluminationPass on the GPU: the texels' paths through framepass's BVH in device memory,
// the scene's lights copied with the frame, as a wavefront. One thread a texel traced each path to
// its end (rtgi::run's giTexel), and a warp waited for its longest path: on the dense terrain four
// in five first rays leave the scene, so the hits' light samples and bounces ran with 5 of a
// warp's 32 threads. Here each launch takes one step of every path still going — its light
// samples at the hit, its next ray — over a list of only those, the texel kept between launches
// (TexelPath). Each path runs DiffusePaths.h's steps in the order giTexel runs them, so the
// bits are the CPU's.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/rt_global_illumination/RTGlobalIlluminationKernel.h"
#include "passes/rt_global_illumination/RTGlobalIlluminationPass.h"

#include <cuda_runtime.h>

#include <array>

namespace fp {

namespace {
// A launch over a list lays it out in rows of this many entries (its 16×8 blocks each take 16
// entries of 8 rows): a launch of one row would leave seven of a block's eight rows idle.
constexpr int kListRow = 1024;
constexpr const char* kWhat = "rt_global_illumination";

/// What the wavefront keeps of a texel between launches: the texel, its path in flight and the
/// hit whose lights the path draws next.
struct TexelPath {
    rtgi::Texel texel;
    PathState path;
    SurfacePoint hit;
};

/// The wavefront's texels, each launch's list of the paths that go on and its length.
struct Wavefront {
    TexelPath* slots;  // texel i = y · width + x
    int width;
    int* next;
    unsigned* length;
};

/// Texel path `s` (texel i, its path k) after a ray step: where the path goes on (`goesOn`, its
/// hit found) it is kept and listed for the next launch; otherwise its share is added and the
/// texel's outputs written after its last path, or the texel kept for its next.
FP_HD inline void keepOrEnd(const rtgi::Frame& f, const Wavefront& w, TexelPath& s, bool goesOn,
                            const PathHit& hit, int i, int k) {
    if (goesOn) {
        s.hit = hit.surface;
        w.slots[i] = s;
        cuda::appendToList(w.length, w.next, i);
        return;
    }
    rtgi::addPath(f.setup, s.texel, s.path.out);
    if (k + 1 < f.setup.spp)
        w.slots[i].texel = s.texel;
    else
        rtgi::writeTexel(f, s.texel, i % w.width, i / w.width);
}

}  // namespace

void RTGlobalIlluminationPass::executeCuda(PassContext& ctx) {
    using namespace rtgi;
    const DevicePorts ports{ctx};
    const DirectLighting lighting(ctx.scene(), 1);
    std::shared_ptr<const LightView> lights;
    const BvhTracer tracer = bvhTracerFor(ports, lighting, lights);
    const Extent trace = outputExtents(kDiffuse, ctx.frame().extent).front();
    const Frame f = frameOf(ports, frameSetup(ctx), trace);
    const int texels = trace.width * trace.height;
    const auto slots = ports.scratchArray<TexelPath>(std::size_t(texels));
    const auto lists = ports.scratchArray<int>(2 * std::size_t(texels));
    const auto length = ports.scratchArray<unsigned>(1);
    Wavefront w{slots.get(), trace.width, lists.get(), length.get()};
    const DiffusePathSettings& c = f.setup.paths;

    std::array<uint64_t, kCounterCount> total{};
    auto add = [&](const std::array<uint64_t, kCounterCount>& counts) {
        for (int i = 0; i < kCounterCount; ++i) total[i] += counts[i];
    };
    auto listLength = [&] {
        unsigned n = 0;
        cuda::checkStatus(cudaMemcpy(&n, w.length, sizeof n, cudaMemcpyDeviceToHost), kWhat);
        return n;
    };
    auto clearList = [&](int* list) {
        w.next = list;
        cuda::checkStatus(cudaMemsetAsync(w.length, 0, sizeof(unsigned)), kWhat);
    };
    for (int k = 0; k < f.setup.spp; ++k) {
        // Every texel: its set-up (the first path) or what its last path left, path k's first
        // ray. A warp traces 8×4 neighbouring texels' rays (CudaLaunch.cuh's PixelBlock).
        clearList(lists.get());
        add(CudaPixels{cuda::PixelBlock::Squares}.forEach<kCounterCount>(
            trace.width, trace.height,
            [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& n) {
                const int i = y * w.width + x;
                TexelPath s;
                if (k == 0) {
                    s.texel = texelAt(f, x, y);
                    if (!s.texel.traced) {
                        if (f.setup.spp > 1) w.slots[i].texel = s.texel;
                        writeTexel(f, s.texel, x, y);
                        ++n.value[kSkipped];
                        return;
                    }
                    ++n.value[kPixels];
                } else {
                    s.texel = w.slots[i].texel;
                    if (!s.texel.traced) return;
                }
                s.path = texelPath(f.setup, s.texel);
                PathHit hit;
                const bool goesOn = pathRayStep(tracer, c, s.path, hit, n.value[kRays]);
                keepOrEnd(f, w, s, goesOn, hit, i, k);
            },
            kWhat));
        // The paths that go on, one step a launch: the lights at their hit, their next ray.
        for (int from = 0;; from ^= 1) {
            const unsigned count = listLength();
            if (count == 0) break;
            const int* const list = lists.get() + std::size_t(from) * texels;
            clearList(lists.get() + std::size_t(from ^ 1) * texels);
            add(CudaPixels{}.forEach<kCounterCount>(
                kListRow, int((count + kListRow - 1) / kListRow),
                [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& n) {
                    const unsigned entry = unsigned(y) * kListRow + unsigned(x);
                    if (entry >= count) return;
                    const int i = list[entry];
                    TexelPath s = w.slots[i];
                    pathLightStep(tracer, c, s.path, s.hit, s.texel.rng, n.value[kShadowRays]);
                    PathHit hit;
                    const bool goesOn =
                        !s.path.done && pathRayStep(tracer, c, s.path, hit, n.value[kRays]);
                    keepOrEnd(f, w, s, goesOn, hit, i, k);
                },
                kWhat));
        }
    }
    ctx.addWork("rays", total[kRays]);
    ctx.addWork("shadowRays", total[kShadowRays]);
    ctx.addWork("pixels", total[kPixels]);
    ctx.addWork("skippedPixels", total[kSkipped]);
}

}  // namespace fp
