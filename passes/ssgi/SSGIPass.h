#pragma once
// Screen-space diffuse indirect (algorithms §4, Unreal's SSRTDiffuseIndirect): per pixel, cosine-
// distributed rays around the view-space normal are marched through the furthest HZB in device Z;
// a hit gathers last frame's reduced colour (prev_color_reduction) at the HZB level the ray
// reached. The result is the mean incoming radiance of the rays (irradiance/π) and an AO term,
// 1 − the fraction of rays that found an occluder on screen.
#include "foundation/Math.h"
#include "framework/Params.h"
#include "framework/Pass.h"

namespace fp {

struct SSGIParams {
    int quality = 4;       //!< 1..4 → 4/8/16/32 rays, 8/8/8/12 steps
    int rays = 0;          //!< rays per pixel in place of the quality's count (0: the quality's)
    bool halfRes = false;  //!< trace at half resolution
    float indirectLightingColorScale = 1.0f;  //!< 4.27's PP IndirectLightingIntensity × colour
    bool lanes = true;  //!< CPU: a pixel's rays in SIMD lanes (false: the scalar reference)
};

/// What one quality level costs (algorithms §4.2).
struct SSGIQuality {
    int rays;   //!< rays per pixel
    int steps;  //!< HZB samples per ray, in batches of 4
};

class SSGIPass final : public PassWithParams<SSGIParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    std::vector<Extent> outputExtents(std::string_view port, Extent frame) const override;

    static SSGIQuality qualityTable(int quality);
    /// The quality's steps with `rays` rays per pixel, or its own count when `rays` is 0.
    static SSGIQuality traced(int quality, int rays);
    static constexpr int kMaxRays = 1024;
    /// Trace resolution: the frame, or half of it rounded up (algorithms §4.3).
    static Extent traceExtent(Extent frame, bool halfRes);
    /// Ray `index` of `count` of trace pixel (x, y) on frame index `frameMod8`, in view space around
    /// unit view-space normal `n` (algorithms §4.4: PCG seed, Hammersley, concentric-disk cosine).
    static Vec3f rayDirection(const Vec3f& n, int x, int y, uint32_t frameMod8, int index,
                              int count);

    FP_PASS_HAS_CUDA_KERNEL  // SSGIPass.cu
};

}  // namespace fp
