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
        {"r.RayTracing.Shadows", "", "", "ray-traced shadows: not emulated yet"},
        {"r.Shadow.Denoiser", "", "", "shadow denoiser: not emulated yet"},
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
