#pragma once
// Screen-space reflections (Unreal's SSRTReflections, algorithms §5): per pixel a mirror ray or
// several GGX (visible-normal) rays, set up and marched through the furthest HZB by the same code
// as SSGI (common/HzbMarch.h) with SSR's tolerance, jitter, roughness-scaled level schedule and
// interpolated hit; each hit reprojected into last frame and read from its colour (TAA history),
// vignetted at both screens' edges, Karis-averaged. Pixels rougher than the fade's cutoff are
// skipped (Unreal's stencil pre-pass) and counted. The output is premultiplied radiance with
// coverage in alpha; the EnvBRDF is applied later, in reflection_environment. With r.SSR.Temporal
// the reflection is smoothed across frames: last frame's result, reprojected through the pixel's
// surface and clamped to the 3×3 neighbourhood of this frame's, moves 1/8 of the way to it.
#include "framework/Params.h"
#include "framework/Pass.h"

namespace fp {

struct SSRParams {
    int quality = 3;             //!< r.SSR.Quality 0–4
    int postProcessQuality = 50;  //!< PP ScreenSpaceReflectionQuality 0–100 (Unreal's default 50)
    float maxRoughness = 0.6f;   //!< PP ScreenSpaceReflectionMaxRoughness
    float intensity = 100.0f;    //!< PP ScreenSpaceReflectionIntensity 0–100
    bool temporal = false;       //!< r.SSR.Temporal: smooth across frames with its own history
};

/// One row of the quality table (algorithms §5.1).
struct SSRQuality {
    int level;    //!< 0 off, 1 Low … 4 Epic
    int steps, rays;
    bool glossy;  //!< VNDF-sampled rays (High, Epic) rather than a mirror ray
};

class SSRPass final : public PassWithParams<SSRParams> {
public:
    static ParamSpec<Params> paramSpec() { return paramSpecOf<Params>(); }
    /// SSR's parameters declared for `P`: SSRParams, or a struct extending it (the reflection
    /// hybrid's), so both declare them once.
    template <class P>
    static ParamSpec<P> paramSpecOf();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    PassMemory memoryBytes(Extent frame) const override;

    FP_PASS_HAS_CUDA_KERNEL  // SSRPass.cu

    /// ssr::effectiveQuality (SSRKernel.h): Unreal's GetSSRQualityForView.
    static SSRQuality effectiveQuality(int cvar, int postProcessQuality, float intensity);

    /// ssr::roughnessFade (SSRKernel.h): the fade of §5.2; ≤ 0 skips the pixel.
    static float roughnessFade(float roughness, float maxRoughness, int qualityLevel);
};


template <class P>
ParamSpec<P> SSRPass::paramSpecOf() {
    ParamSpec<P> s;
    s.add("quality", &P::quality,
          "0 off; 1 Low (8 steps, 1 mirror ray), 2 Medium (16, 1 mirror), 3 High (8 steps × 4 GGX "
          "rays), 4 Epic (12 × 12); capped by postProcessQuality")
        .range(0, 4)
        .cvar("r.SSR.Quality");
    s.add("postProcessQuality", &P::postProcessQuality,
          "post-process ScreenSpaceReflectionQuality: ≥ 80 allows Epic, ≥ 60 High, ≥ 40 Medium "
          "(Unreal's default 50 caps SSR at Medium)")
        .range(0, 100);
    s.add("maxRoughness", &P::maxRoughness,
          "post-process ScreenSpaceReflectionMaxRoughness: the fade reaches 0 here (half of it "
          "below High); rougher pixels are skipped")
        .range(0.01, 1.0)
        .cvar("r.SSR.MaxRoughness");
    s.add("intensity", &P::intensity,
          "post-process ScreenSpaceReflectionIntensity (percent); below 1 SSR is off")
        .range(0.0, 100.0);
    s.add("temporal", &P::temporal,
          "smooth the reflection across frames: last frame's, reprojected and clamped to this "
          "frame's 3×3 neighbourhood, moves 1/8 of the way to this frame's")
        .needsHistory()
        .cvar("r.SSR.Temporal");
    return s;
}

}  // namespace fp
