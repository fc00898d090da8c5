#pragma once
// rt_ambient_occlusion's set-up and rays with a row's pixels in SIMD lanes (the widest x86
// instruction set the CPU has, chosen at run time): each pixel's set-up (its position from depth
// and its geometric normal from the neighbours' depths in double, the lobe overlap, the rays'
// frame) and each sample's ray (its random pair, the cosine direction, the weight, the origin's
// bias) are the kernel's own setupPixel and sampleRay (RTAmbientOcclusionKernel.h) over float
// lanes, written as structures of arrays. The scalar reference (RTAmbientOcclusionPass.cpp with
// lanes=false) runs the same functions one pixel at a time; every lane does its IEEE operations
// in the same order, so both give the same bits (RTAmbientOcclusionTests checks it on every
// instruction set the CPU runs).
#include "foundation/PlaneView.h"
#include "foundation/Tiles.h"
#include "passes/rt_ambient_occlusion/RTAmbientOcclusionKernel.h"

#include <cstdint>

namespace fp::rtao {

constexpr int kMaxLanes = 16;                         // AVX-512's floats
constexpr int kRowCapacity = kTileSize + kMaxLanes;  // a tile row, padded to whole vectors

/// Pixels [x0, x0 + count) of row y, and the planes they and their neighbours are read from.
struct RowInputs {
    int x0 = 0, y = 0, count = 0;
    PlaneView depth, model, normal[3];
};

/// What stays the same for every sample of a row's pixels, one array a field; entry i is pixel
/// x0 + i. Inactive pixels (unlit, sky) trace nothing and hold no meaningful values.
struct RowPixels {
    int count = 0;
    int32_t active[kRowCapacity];
    float px[kRowCapacity], py[kRowCapacity], pz[kRowCapacity];
    float sx[kRowCapacity], sy[kRowCapacity], sz[kRowCapacity];  // shading normal
    float gx[kRowCapacity], gy[kRowCapacity], gz[kRowCapacity];  // geometric normal
    float tx[kRowCapacity], ty[kRowCapacity], tz[kRowCapacity];  // tangent
    float bx[kRowCapacity], by[kRowCapacity], bz[kRowCapacity];  // bitangent
    float ex[kRowCapacity], ey[kRowCapacity], ez[kRowCapacity];  // unit, towards the eye
    float eyeDistance[kRowCapacity];
    float overlap[kRowCapacity];  // shadingDotGeometric
    uint32_t rng[kRowCapacity];
};

/// One sample's ray of every pixel of a row (entry i: pixel x0 + i; meaningful where active).
struct RowRays {
    float ox[kRowCapacity], oy[kRowCapacity], oz[kRowCapacity];
    float dx[kRowCapacity], dy[kRowCapacity], dz[kRowCapacity];
    float weight[kRowCapacity];
};

/// Pixels one vector holds on this CPU (16 with AVX-512).
int lanes();
/// Fills `out` for the row (SIMD lanes).
void setupRow(const FrameSetup& s, const RowInputs& in, RowPixels& out);
/// The next sample's ray of every active pixel of the row (SIMD lanes), advancing their streams.
void sampleRow(const FrameSetup& s, RowPixels& px, RowRays& rays);

}  // namespace fp::rtao
