#pragma once
// The screen-space denoiser's stages for the ray-traced signals (algorithms §12.5): one framework,
// three presets, as Unreal runs its AmbientOcclusion, DiffuseAndAmbientOcclusion and Reflections
// signals — a reconstruction, pre-convolutions, a temporal accumulation and a history
// convolution, each stage a bilateral gather over the stage before it. Its kernels are sized by
// the rays' hit distance: a signal varies over a surface about as fast as the things its rays hit
// are near (for reflections, times the lobe's width), so a far hit allows a wide blur and a near
// one keeps it tight.
#include "foundation/Image.h"
#include "framework/Params.h"
#include "framework/Pass.h"

#include <cstdint>
#include <string>
#include <vector>

namespace fp::ssd {

inline constexpr const char* kHitDistance = "hitDistance";
constexpr int kMaxSignalChannels = 4;
/// Unreal clamps the reconstruction samples to [1, 56] (its sample sets' length).
constexpr int kMaxReconstructionSamples = 56;
/// The widest kernel of any stage, pixels (framepass's choice: §12.5).
constexpr float kMaxKernelPixels = 8.0f;

/// How a pixel's kernel radius follows from its hit distance (§12.5).
enum class Footprint {
    Diffuse,   //!< radius = the hit distance (AO, diffuse GI)
    Specular,  //!< radius = the hit distance × the GGX lobe's width α = roughness²
};

/// A preset's stages (Unreal's per-signal cvars set them).
struct Stages {
    Footprint footprint = Footprint::Diffuse;
    int reconstructionSamples = 16;   //!< taps besides the centre, clamped to [1, 56]
    int preConvolutions = 1;          //!< further 8-tap gathers over the reconstruction
    bool temporalAccumulation = true;
    float targetSamples = 4096.0f;    //!< the history's sample count is capped here
    int historyConvolutionSamples = 1;
    float historyConvolutionSpread = 3.0f;  //!< its taps' disc radius, pixels
};

/// How many frame pixels a signal texel spans along each axis: k when `signal` is the frame's
/// extent divided by k (rounded up) for k = 1..4 (a ray-traced pass's screen percentage), else 0.
int upscaleOf(Extent frame, Extent signal);

/// The state a temporal preset keeps between frames: the signal (4 channels, unused ones 0), its
/// sample count, and the surface (view depth, normal) that next frame's validation compares with.
const std::vector<std::string>& stateChannels();

/// What a denoising pass asks of ssd::run (SignalDenoiserKernel.h), the same on both backends:
/// the stages, the ports whose planes (in order) make the signal, and whether to denoise at all
/// (the denoiser cvar above 0; else the raw signal goes through).
struct Denoising {
    Stages stages;
    std::vector<std::string> signalPorts;
    bool enabled = true;
};

/// Unreal's console variables of one signal's denoiser.
struct DenoiserCvars {
    const char* selector;  //!< 0 off, 1 the default denoiser, 2 a third-party one
    const char* prefix;    //!< the signal's settings: PREFIX.ReconstructionSamples, …
};

/// The parameters of a denoising pass, declared once for the three: each pass's own Params
/// struct holds `denoiser`, `reconstructionSamples`, `preConvolution`, `temporalAccumulation`
/// and, where its signal has a history convolution, `historyConvolutionSamples` and
/// `historyConvolutionSpread`, with its signal's defaults.
template <class P>
ParamSpec<P> denoiserParamSpec(const DenoiserCvars& cvars) {
    const std::string prefix = cvars.prefix;
    ParamSpec<P> s;
    s.add("denoiser", &P::denoiser, "0 passes the raw signal through; 1 (and 2) denoise")
        .range(0, 2)
        .cvar(cvars.selector);
    s.add("reconstructionSamples", &P::reconstructionSamples,
          "taps of the spatial reconstruction (Unreal clamps them to 1–56)")
        .range(1, kMaxReconstructionSamples)
        .cvar(prefix + ".ReconstructionSamples");
    s.add("preConvolution", &P::preConvolution, "8-tap pre-convolution passes after it")
        .range(0, 8)
        .cvar(prefix + ".PreConvolution");
    s.add("temporalAccumulation", &P::temporalAccumulation, "accumulate across frames")
        .needsHistory()
        .cvar(prefix + ".TemporalAccumulation");
    if constexpr (requires { &P::historyConvolutionSamples; }) {
        s.add("historyConvolutionSamples", &P::historyConvolutionSamples,
              "taps of the history convolution, the post filter after the accumulation (0: none)")
            .range(0, kMaxReconstructionSamples)
            .cvar(prefix + ".HistoryConvolution.SampleCount");
        s.add("historyConvolutionSpread", &P::historyConvolutionSpread,
              "the history convolution's radius, pixels")
            .range(0.0, 64.0)
            .cvar(prefix + ".HistoryConvolution.KernelSpreadFactor");
    }
    return s;
}

/// The stages a denoising pass's parameters ask for (denoiserParamSpec's members).
template <class P>
Stages stagesOf(const P& p, Footprint footprint, float targetSamples) {
    Stages s;
    s.footprint = footprint;
    s.reconstructionSamples = p.reconstructionSamples;
    s.preConvolutions = p.preConvolution;
    s.temporalAccumulation = p.temporalAccumulation;
    s.targetSamples = targetSamples;
    if constexpr (requires { p.historyConvolutionSamples; }) {
        s.historyConvolutionSamples = p.historyConvolutionSamples;
        s.historyConvolutionSpread = p.historyConvolutionSpread;
    } else {
        s.historyConvolutionSamples = 0;
    }
    return s;
}

/// The inputs every denoising pass declares besides its signal: the rays' hit distance, the
/// GBuffer's depth, normal and shading model (roughness too for reflections), optional velocity.
std::vector<PortSpec> denoiserInputs(Footprint footprint);

/// What run() (SignalDenoiserKernel.h) allocates for a frame of `frame` pixels and a signal of `channels`: the
/// surface grid, the kernel radii, the two ping-pong images, the new state (and the history
/// kept) when accumulating; nothing when not `enabled`. A signal traced at 1/k adds a grid of
/// 1/k² (not counted: at most a quarter of the grid).
PassMemory memoryOf(Extent frame, int channels, bool enabled, bool temporalAccumulation);

}  // namespace fp::ssd
