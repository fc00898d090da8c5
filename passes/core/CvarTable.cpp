#include "passes/core/CvarTable.h"

namespace fp {

CvarTable::CvarTable() {
    mEntries = {
        {"r.SSGI.LeakFreeReprojection", "prev_color_reduction", "leakFree",
         "1 (default): leak-free previous colour + depth; 0: TAA history (reference §3.1)"},
        {"r.SSGI.Enable", "", "", "the SSGI chain is selected by the config's passes"},
        {"r.SSGI.Quality", "", "", "SSGI ray march: not emulated yet"},
        {"r.SSGI.HalfRes", "", "", "SSGI ray march: not emulated yet"},
        {"r.DynamicGlobalIlluminationMethod", "", "", "UE5 GI method: not emulated yet"},
        {"r.DiffuseIndirect.HalfRes", "", "", "UE5 half-resolution diffuse indirect: not emulated yet"},
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

std::vector<std::string> CvarTable::names() const {
    std::vector<std::string> n;
    for (const auto& e : mEntries) n.push_back(e.cvar);
    return n;
}

}  // namespace fp
