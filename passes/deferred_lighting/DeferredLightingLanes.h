#pragma once
// deferred_lighting's rect-light integral for default-lit pixels a SIMD vector at a time on the
// CPU (the widest x86 instruction set the CPU has, chosen at run time). A rect light is an N×N
// grid of points and every point needs the whole default-lit BxDF: sixteen a pixel at the default
// grid. Here neighbouring pixels share a vector and each grid point is one pass over it. The
// arithmetic is DeferredLightingKernel.h's rectDefaultLit, the kernel's own code over lanes
// (foundation/LaneFloat.h), so the sums are the scalar reference's bits (DeferredLightingTests
// checks it on every instruction set the CPU runs).
namespace fp::deferred_lighting {
struct LightShape;
}

namespace fp::deferred {

constexpr int kMaxLanes = 16;  // AVX-512

/// Up to lanes() default-lit pixels, one a lane (structure of arrays). Lanes past `count` are
/// ignored.
struct PixelLanes {
    int count = 0;
    float px[kMaxLanes], py[kMaxLanes], pz[kMaxLanes];  // camera-relative position
    float vx[kMaxLanes], vy[kMaxLanes], vz[kMaxLanes];  // normalize(−p): towards the eye
    float nx[kMaxLanes], ny[kMaxLanes], nz[kMaxLanes];  // the unit normal
    float diffuseR[kMaxLanes], diffuseG[kMaxLanes], diffuseB[kMaxLanes];
    float specularR[kMaxLanes], specularG[kMaxLanes], specularB[kMaxLanes];  // F0
    float roughness[kMaxLanes];
    float surfaceShadow[kMaxLanes], transmissionShadow[kMaxLanes];
};

/// Each pixel's light from the grid points in front of the emitter (shadePixel's sum), and
/// whether any point was (none: the pixel is out of the light's reach).
struct LaneSums {
    float r[kMaxLanes], g[kMaxLanes], b[kMaxLanes];
    bool reached[kMaxLanes];
};

/// Pixels one call takes on this CPU (8 with AVX2, 16 with AVX-512).
int lanes();
/// The default-lit BxDF of every pixel of `in` integrated over the rect `light`'s grid.
void shadeRectDefaultLit(const deferred_lighting::LightShape& light, const PixelLanes& in, LaneSums& out);

}  // namespace fp::deferred
