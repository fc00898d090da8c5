// SSGILanes.h: compiled once per x86 instruction set (foreach_target.h re-includes this file);
// traceInLanes calls the widest one the CPU has. With SSE4 and AVX2 (and the scalar fallback) the
// build is the kernel's own ssgiPixel over LaneFloat<the target's float lanes> (a pixel's rays a
// vector at a time), inlined whole (flatten) so it compiles to that instruction set.
//
// With AVX-512 it is still a second spelling of the kernel in Highway's operations (below), kept
// equal by SSGITests' bit-for-bit test: the templated kernel at 16 lanes, with LaneFloat.h's
// AVX-512 comparisons and AVX-512's gather in the march, measured 13–16 % slower than this code
// (its hit colours and table reads are a load a lane; docs/results/speed-1080p.md). Every lane of it does the
// scalar reference's arithmetic (rayDirection, screenRaySteps, marchHzb) in the same order, one
// IEEE operation for one, with no fused multiply-add (-ffp-contract=off): the disk angle's sine
// and cosine (SinCos.h, in double lanes), the march, the colour reads of the hits (one gather per
// reduced mip the hits reached) and their Karis weights; only the sum of the hits' weighted
// colours stays scalar, in ray order.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/ssgi/SSGILanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "foundation/LaneFloat.h"
#include "foundation/PerPixel.h"
#include "passes/ssgi/SSGILanes.h"
#include "passes/ssgi/SSGIPass.h"
#include "screenspace/LaneMath.h"

#include <cmath>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace fp::ssgi::HWY_NAMESPACE {

#if HWY_TARGET <= HWY_AVX3  // the 512-bit targets: Highway's operations
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<D>;
using V = hn::Vec<D>;
using VI = hn::Vec<DI>;
using M = hn::Mask<D>;

constexpr int kMaxLanes = HWY_MAX_BYTES / sizeof(float);  // 16 with AVX-512
constexpr int kMaxRays = SSGIPass::kMaxRays;

using fp::HWY_NAMESPACE::maxLike;
using fp::HWY_NAMESPACE::minLike;
using fp::HWY_NAMESPACE::concentricDiskLanes;

// hzbCell's index in lanes: floorToInt(v, 0, hi) — the clamp leaves v ≥ 0, so truncation floors.
HWY_INLINE VI clampedFloor(V v, V hi) {
    const D d;
    V c = hn::IfThenElse(v >= hn::Zero(d), v, hn::Zero(d));  // NaN gives 0
    c = hn::IfThenElse(c <= hi, c, hi);
    return hn::ConvertTo(DI(), c);
}

// deviceZFromDepth(depth · w) in double precision, then rounded to float, as raySteps computes the
// ray end's device Z: P22 + P23 / (depth · w), or P22 for an infinite depth.
HWY_INLINE V endDeviceZ(double depth, V w, double zScale, double zOffset) {
    const D d;
#if HWY_TARGET == HWY_SCALAR  // one lane: no halves to promote
    const double z = depth * double(hn::GetLane(w));
    return hn::Set(d, float(std::isinf(z) ? zScale : zScale + zOffset / z));
#else
    const hn::Half<D> dh;
    const hn::Rebind<double, hn::Half<D>> dd;
    const auto deviceZ = [&](auto wHalf) {
        const auto z = hn::Set(dd, depth) * hn::PromoteTo(dd, wHalf);
        return hn::DemoteTo(dh, hn::IfThenElse(hn::IsInf(z), hn::Set(dd, zScale),
                                               hn::Set(dd, zScale) + hn::Set(dd, zOffset) / z));
    };
    return hn::Combine(d, deviceZ(hn::UpperHalf(dh, w)), deviceZ(hn::LowerHalf(dh, w)));
#endif
}

// One pixel's rays, a vector at a time, then its outputs: ssgiPixel's results.
void tracePixel(const Frame& f, int x, int y, const float* indexOverCount, const int32_t* reversed,
                double zScale, double zOffset, unsigned long long* counts) {
    PixelStart p;
    if (!beginPixel(f, x, y, counts, p))
        return;
    const TraceSetup& s = f.setup;
    const D d;
    const DI di;
    const int N = int(hn::Lanes(d));
    const bool wantDistance = bool(f.hitDistance);

    // rayDirection's per-pixel part: the PCG seed and the tangent frame.
    const ue::Rand3 seed = ue::rand3DPCG16(x, y, int32_t(s.frameMod8));
    const float seedOffset = float(seed.x & 0xFFFFu) * (1.0f / 65536.0f);
    Vec3f t, b;
    orthonormalBasis(p.nView, t, b);

    PixelTrace trace;
    unsigned hzbSamples = 0;
    HWY_ALIGN float hitAt[kMaxLanes],
        levelAt[kMaxLanes], ox[kMaxLanes], oy[kMaxLanes], oz[kMaxLanes], sx[kMaxLanes],
        sy[kMaxLanes], sz[kMaxLanes], tol[kMaxLanes];
    for (int r0 = 0; r0 < s.rays; r0 += N) {
        const int n = std::min(N, s.rays - r0);
        const M inUse = hn::FirstN(d, size_t(n));

        // hammersley16 and concentricDisk (UnrealRandom.h).
        const V a = hn::LoadU(d, indexOverCount + r0) + hn::Set(d, seedOffset);
        const V e1 = a - hn::Floor(a);
        const VI bits = hn::And(hn::Xor(hn::LoadU(di, reversed + r0), hn::Set(di, int32_t(seed.y))),
                                hn::Set(di, 0xFFFF));
        const V e2 = hn::ConvertTo(d, bits) * hn::Set(d, 1.0f / 65536.0f);
        V dx, dy;
        concentricDiskLanes(d, e1, e2, dx, dy);
        const V dz = hn::Sqrt(maxLike(hn::Zero(d), hn::Set(d, 1.0f) - dx * dx - dy * dy));
        const V Lx = hn::Set(d, t.x) * dx + hn::Set(d, b.x) * dy + hn::Set(d, p.nView.x) * dz;
        const V Ly = hn::Set(d, t.y) * dx + hn::Set(d, b.y) * dy + hn::Set(d, p.nView.y) * dz;
        const V Lz = hn::Set(d, t.z) * dx + hn::Set(d, b.z) * dy + hn::Set(d, p.nView.z) * dz;

        // raySteps (SSGIKernel.h).
        const V wv = maxLike(hn::Set(d, 1.0f) + Lz, hn::Set(d, 1e-6f));
        const V vsx = hn::Set(d, p.sx), vsy = hn::Set(d, p.sy);
        const V ex = (vsx + hn::Set(d, s.fx) * Lx + hn::Set(d, s.cx) * Lz) / wv;
        const V ey = (vsy + hn::Set(d, s.fy) * Ly + hn::Set(d, s.cy) * Lz) / wv;
        V stepX = ex - vsx, stepY = ey - vsy;
        V stepZ = endDeviceZ(p.depth, wv, zScale, zOffset) - hn::Set(d, p.z0);
        const V zero = hn::Zero(d);
        V fit = hn::Set(d, std::numeric_limits<float>::infinity());
        fit = hn::IfThenElse(stepX > zero, minLike(fit, (hn::Set(d, 1.0f) - vsx) / stepX), fit);
        fit = hn::IfThenElse(stepX < zero, minLike(fit, (hn::Set(d, -1.0f) - vsx) / stepX), fit);
        fit = hn::IfThenElse(stepY > zero, minLike(fit, (hn::Set(d, 1.0f) - vsy) / stepY), fit);
        fit = hn::IfThenElse(stepY < zero, minLike(fit, (hn::Set(d, -1.0f) - vsy) / stepY), fit);
        const M traced = hn::And(inUse, hn::IsFinite(fit));  // others: a miss, no samples
        stepX = stepX * fit;
        stepY = stepY * fit;
        stepZ = stepZ * fit;
        const V invSteps = hn::Set(d, s.invSteps);
        const V tolerance =
            maxLike(hn::Abs(stepZ), hn::Set(d, (p.z0 - p.zTwice) * kToleranceScale)) * invSteps;
        const V stepHx = stepX * hn::Set(d, 0.5f) * hn::Set(d, s.halfW) * invSteps;
        const V stepHy = hn::Neg(stepY) * hn::Set(d, 0.5f) * hn::Set(d, s.halfH) * invSteps;
        const V stepZ1 = stepZ * invSteps;
        const V offset = hn::Set(d, p.stepOffset);
        const V originHx = hn::Set(d, p.start.hx) + stepHx * offset;
        const V originHy = hn::Set(d, p.start.hy) + stepHy * offset;
        const V originZ = hn::Set(d, p.start.z) + stepZ1 * offset;

        // marchHzb (HzbMarch.h): every lane's level follows the same schedule, so a batch reads
        // the same two mips in every lane; a lane drops out after the batch of its first hit.
        V hitSample = hn::Set(d, -1.0f);
        V level = hn::Set(d, 1.0f);
        M marching = traced;
        float batchLevel = 1.0f;
        for (int batch = 0; batch * 4 < s.steps && !hn::AllFalse(d, marching); ++batch) {
            const int mips[2] = {nearestMip(batchLevel, s.hzb.mipCount),
                                 nearestMip(batchLevel + s.levelStep, s.hzb.mipCount)};
            for (int pair = 0; pair < 2; ++pair) {
                const PlaneView& cells = s.hzb.mips[mips[pair]];
                const V scale = hn::Set(d, inversePowerOfTwo(mips[pair]));
                const V maxX = hn::Set(d, float(cells.width - 1));
                const V maxY = hn::Set(d, float(cells.height - 1));
                const VI stride = hn::Set(di, int32_t(cells.stride));
                for (int j = 0; j < 2; ++j) {
                    const int k = batch * 4 + pair * 2 + j + 1;
                    const V kf = hn::Set(d, float(k));
                    const V rz = originZ + stepZ1 * kf;
                    const VI cx = clampedFloor((originHx + stepHx * kf) * scale, maxX);
                    const VI cy = clampedFloor((originHy + stepHy * kf) * scale, maxY);
                    const V hz = hn::GatherIndex(d, cells.data, cy * stride + cx);
                    const V diff = rz - hz;
                    const M hit = hn::And(hn::And(marching, hitSample < zero),
                                          hn::And(hz > zero, hn::Abs(diff + tolerance) < tolerance));
                    hitSample = hn::IfThenElse(hit, kf, hitSample);
                }
            }
            hzbSamples += 4u * unsigned(hn::CountTrue(d, marching));
            batchLevel += 2.0f * s.levelStep;
            level = hn::IfThenElse(marching, hn::Set(d, batchLevel), level);
            marching = hn::And(marching, hitSample < zero);
        }

        const M hits = hn::And(inUse, hitSample >= zero);
        if (hn::AllFalse(d, hits))
            continue;
        if (wantDistance) {
            // The debug distance output: each hit one at a time, as the scalar code shades it.
            hn::Store(hitSample, d, hitAt);
            hn::Store(level, d, levelAt);
            hn::Store(originHx, d, ox);
            hn::Store(originHy, d, oy);
            hn::Store(originZ, d, oz);
            hn::Store(stepHx, d, sx);
            hn::Store(stepHy, d, sy);
            hn::Store(stepZ1, d, sz);
            hn::Store(tolerance, d, tol);
            for (int i = 0; i < n; ++i) {
                if (hitAt[i] < 0.0f)
                    continue;
                const RaySteps steps{{ox[i], oy[i], oz[i]}, {sx[i], sy[i], sz[i]}, tol[i]};
                const RayPoint hit = rayPointAt(steps, hitAt[i]);
                float c[3];
                hitColor(s, hit, levelAt[i], true, c);
                trace.add(weighHit(s, p, hit, c, wantDistance));
            }
            continue;
        }
        // shadeHit in lanes: the hit point (rayPointAt), the colour of the reduced mip nearest
        // the level each ray reached (hitColor; one gather per mip present), the Karis weight;
        // then the sums in ray order, as PixelTrace adds them.
        const V hx = originHx + stepHx * hitSample, hy = originHy + stepHy * hitSample;
        const VI mip = clampedFloor(level + hn::Set(d, 0.5f), hn::Set(d, float(kReducedMips - 1)));
        V c[3] = {zero, zero, zero};
        for (int m = 0; m < kReducedMips; ++m) {
            const M onMip = hn::And(hits, hn::RebindMask(d, mip == hn::Set(di, m)));
            if (hn::AllFalse(d, onMip))
                continue;
            const V scale = hn::Set(d, inversePowerOfTwo(m));
            const VI rx = clampedFloor(hx * scale, hn::Set(d, float(s.reducedMaxX[m])));
            const VI ry = clampedFloor(hy * scale, hn::Set(d, float(s.reducedMaxY[m])));
            for (int ch = 0; ch < 3; ++ch) {
                const PlaneView& plane = s.reduced[m][ch];
                const VI index = ry * hn::Set(di, int32_t(plane.stride)) + rx;
                c[ch] = hn::IfThenElse(onMip, hn::GatherIndex(d, plane.data, index), c[ch]);
            }
        }
        const V luma = hn::Set(d, 0.3f) * c[0] + hn::Set(d, 0.59f) * c[1] + hn::Set(d, 0.11f) * c[2];
        const V karis = hn::Set(d, 1.0f) / (hn::Set(d, 1.0f) + luma);
        HWY_ALIGN float weighted[3][kMaxLanes];
        for (int ch = 0; ch < 3; ++ch)
            hn::Store(c[ch] * karis, d, weighted[ch]);
        hn::Store(hitSample, d, hitAt);
        for (int i = 0; i < n; ++i) {
            if (hitAt[i] < 0.0f)
                continue;
            RayTrace t;
            t.hit = true;
            for (int ch = 0; ch < 3; ++ch)
                t.weighted[ch] = weighted[ch][i];
            trace.add(t);
        }
    }
    counts[kRays] += (unsigned long long)s.rays;
    counts[kHzbSamples] += hzbSamples;
    finishPixel(f, x, y, trace);
}

std::array<uint64_t, kCounterCount> traceFrame(const Frame& f) {
    FP_CHECK(f.setup.rays >= 1 && f.setup.rays <= kMaxRays, "SSGI traces 1 to {} rays, not {}",
             kMaxRays, f.setup.rays);
    // hammersley16's per-ray terms, float(i)/float(count) and the reversed bits of i, padded to
    // whole vectors.
    HWY_ALIGN float indexOverCount[kMaxRays + kMaxLanes] = {};
    HWY_ALIGN int32_t reversed[kMaxRays + kMaxLanes] = {};
    for (int i = 0; i < f.setup.rays; ++i) {
        indexOverCount[i] = float(uint32_t(i)) / float(uint32_t(f.setup.rays));
        reversed[i] = int32_t(ue::reverseBits32(uint32_t(i)) >> 16u);
    }
    const double zScale = f.setup.cam.projectionZScale(), zOffset = f.setup.cam.projectionZOffset();
    return CpuPixels{}.forEach<kCounterCount>(
        f.ao.width, f.ao.height,
        [&](int x, int y, WorkCounts<kCounterCount>& c) {
            tracePixel(f, x, y, indexOverCount, reversed, zScale, zOffset, c.value);
        },
        "ssgi");
}

LaneTarget target() {
    return {hwy::TargetName(HWY_TARGET), int(hn::Lanes(D()))};
}

#else  // the kernel's own code over lanes

// One lane type per target: 8 floats with AVX2, 4 with SSE (and the scalar fallback, which runs
// 4-wide GCC vectors on the baseline SSE2).
constexpr int kLanesHere = HWY_LANES(float) < 4 ? 4 : int(HWY_LANES(float));
using T = LaneFloat<kLanesHere>;

__attribute__((flatten)) void tracePixel(const Frame& f, int x, int y, unsigned long long* counts) {
    ssgiPixel<T>(f, x, y, counts);
}

std::array<uint64_t, kCounterCount> traceFrame(const Frame& f) {
    FP_CHECK(f.setup.rays >= 1 && f.setup.rays <= SSGIPass::kMaxRays,
             "SSGI traces 1 to {} rays, not {}", SSGIPass::kMaxRays, f.setup.rays);
    return CpuPixels{}.forEach<kCounterCount>(
        f.ao.width, f.ao.height,
        [&](int x, int y, WorkCounts<kCounterCount>& c) { tracePixel(f, x, y, c.value); }, "ssgi");
}

LaneTarget target() {
    return {hwy::TargetName(HWY_TARGET), kLanesHere};
}

#endif

}  // namespace fp::ssgi::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp::ssgi {

HWY_EXPORT(traceFrame);
HWY_EXPORT(target);

std::array<uint64_t, kCounterCount> traceInLanes(const Frame& f) {
    return HWY_DYNAMIC_DISPATCH(traceFrame)(f);
}

LaneTarget laneTarget() {
    return HWY_DYNAMIC_DISPATCH(target)();
}

}  // namespace fp::ssgi
#endif
