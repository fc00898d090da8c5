#pragma once
// A wave's light samples (DiffusePathWave) with its hits in SIMD lanes (the widest x86
// instruction set the CPU has, chosen at run time): each hit's `nee` samples are DiffusePaths.h's
// own drawLightSample over float lanes, the light picked per lane and sampled by DirectLighting.h's
// sampleLightOf, written as structures of arrays. The scalar path (traceDiffusePath) runs the same
// functions one hit at a time; every lane does its IEEE operations in the same order, so both
// give the same bits (RTGlobalIlluminationTests checks it on every instruction set the CPU runs).
#include "shading/DirectLighting.h"

#include <cstdint>
#include <vector>

namespace fp {

/// A step's hits, one array a field, padded to whole vectors by resize(): entry i is hit i.
struct HitLanes {
    int count = 0;
    std::vector<float> px, py, pz;  // the shading point
    std::vector<float> ox, oy, oz;  // its rays' origin (SurfacePoint::rayOrigin)
    std::vector<float> nx, ny, nz;  // the shading normal
    std::vector<float> dr, dg, db;  // the diffuse colour
    std::vector<uint32_t> rng;      // each hit's path's stream, advanced by the samples
    /// Room for `n` hits, whole vectors of the widest lanes.
    void resize(int n);
    /// Entry i: hit `s`, its stream at `state`.
    void set(std::size_t i, const SurfacePoint& s, uint32_t state);
};

/// What each sample of each hit found: entry k · stride + i is hit i's sample k.
struct SampleLanes {
    int stride = 0;
    std::vector<int32_t> keep;        // its light reaches the hit from above: a shadow ray to trace
    std::vector<float> dx, dy, dz;    // the shadow ray's direction
    std::vector<float> tfar;          // and its length
    std::vector<float> lr, lg, lb;    // what the sample adds when unblocked
};

/// Each of `nee` samples of every hit of `hits` (lights: `lights` of them; at least one, and
/// nee ≥ 1), drawn from and advancing each hit's stream.
void drawLightSampleLanes(const LightView* lights, int lightCount, int nee, HitLanes& hits,
                          SampleLanes& out);

}  // namespace fp
