// The explicit list of built-in pass types (architecture anchors B3): one line per pass.
#include "passes/composite/DiffuseIndirectCompositePass.h"
#include "passes/core/PassRegistry.h"
#include "passes/display/DisplayPass.h"
#include "passes/hzb/HZBPass.h"
#include "passes/metrics/ErrorMeasurePass.h"
#include "passes/prevcolor/PrevColorReductionPass.h"
#include "passes/rt_shadows/RtShadowsPass.h"
#include "passes/shadow_denoise/ShadowDenoisePass.h"
#include "passes/deferred_lighting/DeferredLightingPass.h"
#include "passes/ssgi/SsgiPass.h"
#include "passes/ssgi_denoise/SsgiDenoisePass.h"

namespace fp {

const PassRegistry& builtinPasses() {
    static const PassRegistry registry = [] {
        PassRegistry r;
        r.add<HZBPass>("hzb", "furthest and closest hierarchical Z of device depth (reference §2)");
        r.add<PrevColorReductionPass>(
            "prev_color_reduction",
            "previous-frame colour reprojected and reduced to 5 mips, leak-free (reference §3)");
        r.add<SsgiPass>("ssgi", "screen-space diffuse indirect: cosine rays marched through the "
                                "HZB, last frame's colour at the hits, AO (reference §4)");
        r.add<SsgiDenoisePass>("ssgi_denoise", "SSGI denoiser: 8-tap bilateral reconstruction and "
                                               "temporal accumulation (reference §6.2)");
        r.add<DiffuseIndirectCompositePass>(
            "diffuse_indirect_composite",
            "SceneColor × AO + diffuse albedo × SSGI, 4.27 or UE5 per shading model (reference §7)");
        r.add<RtShadowsPass>("rt_shadows", "ray-traced shadows of one light through Embree "
                                           "packets, subsurface transmission, light attenuation "
                                           "(reference §9)");
        r.add<ShadowDenoisePass>("shadow_denoise", "penumbra-aware spatial shadow denoiser: blur "
                                                   "radius from occluder distance and light size "
                                                   "(reference §6.3)");
        r.add<DeferredLightingPass>("deferred_lighting",
                                    "direct lighting of one light per shading model, shadowed by "
                                    "its light attenuation, added to scene colour (reference §9.6)");
        r.add<DisplayPass>("display", "OpenColorIO display transform of a buffer for a PNG preview");
        r.add<ErrorMeasurePass>("error_measure", "error of any output against a reference (a "
                                                 "Truth.* layer): metrics in the report, heat map");
        return r;
    }();
    return registry;
}

}  // namespace fp
