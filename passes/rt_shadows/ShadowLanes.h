#pragma once
// rt_shadows' per-pixel work with a row's pixels in SIMD lanes (the widest x86 instruction set
// the CPU has, chosen at run time): each pixel's set-up (its position rebuilt from depth in double,
// the light's reach, the normal) and each sample's shadow ray (the random pair, N·L culling, the
// biases, the light sample) are the kernel's own setupPixel and sampleRay (RTShadowsKernel.h) over
// float lanes, written as structures of arrays that Embree's packets take without a per-ray copy.
//
// The scalar reference (RTShadowsPass.cpp with lanes=false) runs the same functions with float,
// one pixel at a time. Every lane does its IEEE operations in the same order (no fused
// multiply-add: the build sets -ffp-contract=off; the sample angles' sine and cosine are
// SinCos.h's, in double lanes), so both give the same bits (RTShadowsTests checks it on every
// instruction set the CPU runs).
#include "foundation/Camera.h"
#include "foundation/Tiles.h"
#include "passes/rt_shadows/RTShadowsKernel.h"
#include "passes/rt_shadows/ShadowRayGenerator.h"

#include <cstdint>

namespace fp::shadow {

constexpr int kMaxLanes = 16;                         // AVX-512's floats
constexpr int kRowCapacity = kTileSize + kMaxLanes;  // a tile row, padded to whole vectors

/// The GBuffer of pixels [x0, x0 + count) of row y, one pointer a plane. (Opacity and InstanceId
/// are read only where a transmission ray needs them: most rows have none.)
struct RowInputs {
    int x0 = 0, y = 0, count = 0;
    const float *depth, *normalX, *normalY, *normalZ, *model;
};

/// What stays the same for every sample of a row's pixels, one array a field; entry i is pixel
/// x0 + i. Inactive pixels (unlit, sky, out of the light's reach) trace nothing and hold no
/// meaningful values.
struct RowPixels {
    int x0 = 0, count = 0;
    int32_t active[kRowCapacity];
    float px[kRowCapacity], py[kRowCapacity], pz[kRowCapacity];  // camera-relative position
    float nx[kRowCapacity], ny[kRowCapacity], nz[kRowCapacity];  // bias normal (hair: to light)
    float ex[kRowCapacity], ey[kRowCapacity], ez[kRowCapacity];  // unit, towards the eye
    float eyeDistance[kRowCapacity];
    int32_t model[kRowCapacity];
    uint32_t rng[kRowCapacity];  // each pixel's Rng state (Random.h), advanced per sample
};

/// Rows a strip holds: the rows of a tile whose rays are traced together, so Embree's packets
/// are full (a row's rays alone leave half of each packet's lanes idle on average).
constexpr int kStripRows = 16;
constexpr int kStripRayCapacity = kStripRows * kTileSize + kMaxLanes;

/// One sample's rays of a strip, gathered row by row from the pixels that trace one, in pixel
/// order; padded so a vector's compressed store past the last ray stays inside.
struct StripRays {
    int count = 0;
    alignas(64) float ox[kStripRayCapacity], oy[kStripRayCapacity], oz[kStripRayCapacity];
    alignas(64) float dx[kStripRayCapacity], dy[kStripRayCapacity], dz[kStripRayCapacity];
    alignas(64) float tfar[kStripRayCapacity];
    int32_t owner[kStripRayCapacity];  // the pixel that traced it: ownerOf(row in strip, index)
};

/// A pixel's owner id in StripRays: its row in the strip and its index in that row's RowPixels.
constexpr int32_t ownerOf(int stripRow, int i) {
    return stripRow * kRowCapacity + i;
}
constexpr int ownerRow(int32_t owner) {
    return owner / kRowCapacity;
}
constexpr int ownerIndex(int32_t owner) {
    return owner % kRowCapacity;
}

/// The Rng state of pixel (x, y), as Rng(frame, x, y, seed) seeds it, from the frame's key.
uint32_t rngState(uint32_t key, int x, int y);

/// Pixels one vector holds on this CPU (16 with AVX-512).
int lanes();
/// Fills `out` for the row (SIMD lanes).
void setupRow(const RowContext& c, const RowInputs& in, RowPixels& out);
/// One sample's rays of the active pixels (SIMD lanes): draws each active pixel's random pair
/// and appends the rays of those not culled to `rays`, owned by ownerOf(stripRow, pixel).
void sampleRow(const RowContext& c, int stripRow, RowPixels& px, StripRays& rays);

}  // namespace fp::shadow
