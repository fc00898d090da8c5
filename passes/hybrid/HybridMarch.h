#pragma once
// The hybrid's march recorded (HybridPass::traceWaves, the CPU through Embree): SSGI's kernel runs
// over a tile with a fallback that notes each ray's light in ray order and the scene paths it
// asks for, bringing nothing back; the paths are traced afterwards in waves, and each pixel is
// resolved from the record. recordTileMarch runs the kernel with a pixel's rays in SIMD lanes
// (HybridLanes.cpp), which calls the fallback lane by lane in ray order, as the scalar kernel
// does.
#include "foundation/Tiles.h"
#include "passes/hybrid/HybridKernel.h"
#include "passes/ssgi/SSGIKernel.h"
#include "shading/DiffusePathWave.h"

#include <cstdint>
#include <vector>

namespace fp::hybrid {

using EmbreeFallback = GiFallback<EmbreeTracer>;

/// A tile's march, as SSGI's kernel ran it: each traced pixel's rays in order — an on-screen
/// hit's light, a fallback path, or an on-screen hit continued by a path — and the scene paths
/// those ask for, each pixel's fallback paths drawing from its stream and its continuations
/// from its onward stream; then what each path brought.
struct TileMarch {
    enum Kind : uint8_t { kScreen, kMiss, kContinued };
    struct Ray {
        Kind kind;
        std::size_t path;        // kMiss, kContinued: into misses or continuations
        ssgi::RayTrace screen;   // kScreen: its light, final
        RayPoint hit;            // kContinued: where it hit, and last frame's colour there
        float color[3];
    };
    struct Pixel {
        int x, y;
        std::size_t firstRay, firstMiss, firstContinuation;
        Rng rng, onwardRng;  // its two streams
        bool continuing = false;  // its last ray asked for a continuation
    };
    // The tile's traced pixels, in the order they ran, then one past the last (recordTileMarch
    // closes the record with it): pixel p's rays, misses and continuations run up to pixel
    // p + 1's first.
    std::vector<Pixel> pixels;
    std::size_t tracedPixels() const { return pixels.size() - 1; }
    std::vector<Ray> rays;
    std::vector<PathState> misses;
    std::vector<RayPoint> continuationHits;  // the on-screen hits to continue, as asked
    std::vector<EmbreeFallback::Continuation> continuations;  // and where from (valid or not)
    std::vector<ssgi::RayTrace> missResults;
    std::vector<Vec3f> continuationResults;  // what each adds to its hit's colour
    // A wave's paths and streams.
    std::vector<PathState> going;
    std::vector<Rng*> rngs;
    std::vector<std::size_t> owner;
    DiffusePathWave wave;
};

/// SSGI's fallback (ssgi::NoFallback's shape) that records the march — each ray's light in
/// order, and what it asks of the scene — bringing nothing back from the scene yet. Its calls
/// stay calls (noinline) where the lanes' kernel is inlined whole: they are bookkeeping, built
/// once for the baseline instruction set.
struct RecordingFallback {
    const EmbreeFallback& of;
    TileMarch* march;
    struct Pixel {
        EmbreeFallback::Pixel of;
    };

    __attribute__((noinline)) Pixel begin(const ssgi::Frame& f, int x, int y) const {
        const EmbreeFallback::Pixel p = of.begin(f, x, y);
        march->pixels.push_back({x, y, march->rays.size(), march->misses.size(),
                                 march->continuationHits.size(), p.rng, p.onwardRng});
        return {p};
    }
    bool continuesHits() const { return of.continuesHits(); }
    __attribute__((noinline)) void onScreenHit(Pixel&, const RayPoint& hit, float c[3]) const {
        TileMarch::Ray r{};
        r.kind = TileMarch::kContinued;
        r.path = march->continuationHits.size();
        r.hit = hit;
        for (int ch = 0; ch < 3; ++ch) r.color[ch] = c[ch];
        march->rays.push_back(r);
        march->continuationHits.push_back(hit);
        march->pixels.back().continuing = true;  // addHit follows, with this ray's light
    }
    __attribute__((noinline)) ssgi::RayTrace miss(Pixel& p, int, int, const Vec3f& L) const {
        TileMarch::Ray r{};
        r.kind = TileMarch::kMiss;
        r.path = march->misses.size();
        march->rays.push_back(r);
        march->misses.push_back(of.missPath(p.of, L));
        return {};
    }
    __attribute__((noinline)) void addHit(Pixel&, ssgi::PixelTrace&,
                                          const ssgi::RayTrace& light) const {
        TileMarch::Pixel& pixel = march->pixels.back();
        if (pixel.continuing) {  // its light waits for its path (onScreenHit recorded it)
            pixel.continuing = false;
            return;
        }
        TileMarch::Ray r{};
        r.kind = TileMarch::kScreen;
        r.screen = light;
        march->rays.push_back(r);
    }
    void end(Pixel&) const {}
};

/// The march over tile `t` of `f` recorded into `march` (its arrays cleared first), a pixel's rays
/// in SIMD lanes (the widest x86 instruction set the CPU has); SSGI's work added to `counts`
/// (ssgi::Counter) and the skipped pixels' outputs written, as ssgi::run does.
void recordTileMarch(const ssgi::Frame& f, const Tile& t, const EmbreeFallback& fallback,
                     TileMarch& march, unsigned long long* counts);

}  // namespace fp::hybrid
