#include "passes/core/CvarTable.h"

#include <algorithm>

namespace fp {

CvarTable::CvarTable() {
    mEntries = {
        {"r.SSGI.LeakFreeReprojection", "prev_color_reduction", "leakFree",
         "1 (default): leak-free previous colour + depth; 0: TAA history (reference §3.1)"},
        {"r.SSGI.Enable", "", "", "the SSGI chain is selected by the config's passes"},
        {"r.SSGI.Quality", "ssgi", "quality", "1..4: 4/8/16/32 rays, 8/8/8/12 steps (reference §4.2)"},
        {"r.SSGI.HalfRes", "ssgi", "halfRes", "trace (and denoise) at half resolution (4.27 name)"},
        {"r.SSGI.HalfRes", "ssgi_denoise", "halfRes", "the denoiser runs at the trace resolution"},
        {"r.DynamicGlobalIlluminationMethod", "", "",
         "UE5 GI method: framepass's chain is 2 (screen-space GI); Lumen (1) is not emulated", 2},
        {"r.DiffuseIndirect.HalfRes", "ssgi", "halfRes", "UE5's name for r.SSGI.HalfRes (UE5 default 1)"},
        {"r.DiffuseIndirect.HalfRes", "ssgi_denoise", "halfRes", "the denoiser runs at the trace resolution"},
        {"r.DiffuseIndirect.Denoiser", "ssgi_denoise", "denoiser", "0 off (raw trace), 1 on (2, a third-party denoiser, runs framepass's)"},
        {"r.GlobalIllumination.Denoiser.TemporalAccumulation", "ssgi_denoise", "temporalAccumulation", "temporal accumulation of the SSGI denoiser"},
        {"r.SSR.Quality", "", "", "screen-space reflections: not emulated yet"},
        {"r.RayTracing.Shadows", "", "",
         "shadows are ray traced (rt_shadows) whenever the config names a scene with lights", 1},
        {"r.RayTracing.Shadow.SamplesPerPixel", "rt_shadows", "samplesPerPixel",
         "shadow rays per pixel; −1 = each light's own samplesPerPixel"},
        {"r.RayTracing.NormalBias", "rt_shadows", "normalBias", "largest shadow-ray bias, cm"},
        {"r.RayTracing.Shadows.LODTransitionStart", "rt_shadows", "lodTransitionStart",
         "subsurface visibility blends towards transmission from here, cm"},
        {"r.RayTracing.Shadows.LODTransitionEnd", "rt_shadows", "lodTransitionEnd",
         "... and is transmission from here, cm"},
        {"r.RayTracing.Shadows.EnableTwoSidedGeometry", "", "",
         "shadow rays always see both sides of every triangle (Unreal's default)", 1},
        {"r.RayTracing.Shadows.AcceptFirstHit", "", "",
         "rt_shadows tests occlusion with any hit and finds the closest hit only for blocked rays "
         "whose distance the denoiser reads: the same result as Unreal's default 0", 0},
        {"r.Shadow.Denoiser", "shadow_denoise", "denoiser", "0 off, 1 or 2 on (reference §6.3)"},
        {"r.Shadow.Denoiser.ReconstructionSamples", "shadow_denoise", "reconstructionSamples",
         "taps of each shadow filtering pass"},
        {"r.Shadow.Denoiser.PreConvolution", "shadow_denoise", "preConvolution",
         "shadow filtering passes before the reconstruction"},
    };
}

const CvarMapping* CvarTable::find(const std::string& cvar) const {
    for (const auto& e : mEntries)
        if (e.cvar == cvar) return &e;
    return nullptr;
}

const CvarMapping* CvarTable::find(const std::string& cvar, const std::string& passType) const {
    for (const auto& e : mEntries)
        if (e.cvar == cvar && e.passType == passType) return &e;
    return nullptr;
}

std::vector<std::string> CvarTable::names() const {
    std::vector<std::string> n;
    for (const auto& e : mEntries)
        if (std::find(n.begin(), n.end(), e.cvar) == n.end()) n.push_back(e.cvar);
    return n;
}

}  // namespace fp
