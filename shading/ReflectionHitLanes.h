#pragma once
// A wave of reflection hits' light samples (ReflectionHitWave) in SIMD lanes (the widest x86
// instruction set the CPU has, chosen at run time): every hit samples every light alike, so a
// vector of neighbouring hits takes each light's k-th sample together — DirectLighting.h's own
// stratifiedSampleOf, sampleLightOf and lightValueOf over float lanes. The scalar path
// (shadeLights) runs the same functions one hit at a time; every lane does its IEEE operations in
// the same order, so both give the same bits (RTReflectionsTests checks it on every instruction
// set the CPU runs).
#include "shading/DiffusePathLanes.h"
#include "shading/DirectLighting.h"

#include <cstdint>
#include <vector>

namespace fp {

/// A wave's hits as the lanes read them, one array a field (HitLanes' and the view vector and
/// the specular lobe), padded to whole vectors by resize(): entry i is hit i.
struct ReflectionHitLanes : HitLanes {
    std::vector<float> vx, vy, vz;  // the unit vector to the viewer
    std::vector<float> sr, sg, sb;  // the specular colour (F0)
    std::vector<float> roughness;
    /// Room for `n` hits, whole vectors of the widest lanes.
    void resize(int n);
    /// Entry i: hit `s`, its stream at `state`.
    void set(std::size_t i, const SurfacePoint& s, uint32_t state);
};

/// Every light sample of every hit of `hits` (shadeLights' samples: `samples` of a light with
/// extent, one of a punctual light, in the lights' order), drawn from and advancing each hit's
/// stream: `out` entry s · stride + i is hit i's s-th sample over all the lights, and `lr, lg,
/// lb` what it adds when unblocked (lightValueOf).
void drawLightRayLanes(const LightView* lights, int lightCount, int samples,
                       ReflectionHitLanes& hits, SampleLanes& out);

}  // namespace fp
