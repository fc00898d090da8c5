#pragma once
// A wave's reflection rays (RTReflectionsPass::traceWaves) drawn in SIMD lanes (the widest x86
// instruction set the CPU has, chosen at run time): the kernel's own texelRayOf over float lanes,
// a tile's neighbouring texels a vector. The scalar path (reflectionTexel) runs the same function
// one texel at a time; every lane does its IEEE operations in the same order, so both give the
// same bits (RTReflectionsTests checks it on every instruction set the CPU runs).
#include "shading/RayOriginBias.h"

#include <cstdint>
#include <vector>

namespace fp::rtr {

/// A wave's texels, one array a field, padded to whole vectors by resize(): entry i is texel i.
struct TexelLanes {
    int count = 0;
    std::vector<float> px, py, pz;            // the surface, relative to the scene's origin
    std::vector<float> ex, ey, ez, distance;  // the unit vector to the eye and the distance to it
    std::vector<float> nx, ny, nz, roughness;
    std::vector<uint32_t> rng;                // each texel's stream, advanced by its ray
    std::vector<float> ox, oy, oz, lx, ly, lz;  // the ray drawn: its origin and direction
    /// Room for `n` texels, whole vectors of the widest lanes.
    void resize(int n);
};

/// Each texel's next ray (texelRayOf with `bias`), drawn from its stream.
void drawTexelRayLanes(const RayBias& bias, TexelLanes& texels);

struct Frame;

/// The texels x0 ≤ x < x1 of row y that trace (tracesOf, a vector of the row's pixels at a
/// time), for a trace at full resolution (texel (x, y) is GBuffer pixel (x, y)): their x, in
/// order, to `xs` (room for x1 − x0 + 16 values); returns how many.
int tracingTexelsOfRow(const Frame& f, int y, int x0, int x1, int* xs);

}  // namespace fp::rtr
