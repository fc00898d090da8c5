// The explicit list of built-in pass types (architecture anchors B3): one line per pass.
#include "passes/ao_denoise/AODenoisePass.h"
#include "passes/camera_velocity/CameraVelocityPass.h"
#include "framework/PassRegistry.h"
#include "passes/deferred_lighting/DeferredLightingPass.h"
#include "passes/diffuse_indirect_composite/DiffuseIndirectCompositePass.h"
#include "passes/display/DisplayPass.h"
#include "passes/error_measure/ErrorMeasurePass.h"
#include "passes/gi_denoise/GIDenoisePass.h"
#include "passes/hybrid/HybridPass.h"
#include "passes/hybrid_reflections/HybridReflectionsPass.h"
#include "passes/hzb/HZBPass.h"
#include "passes/prev_color_reduction/PrevColorReductionPass.h"
#include "passes/reflection_denoise/ReflectionDenoisePass.h"
#include "passes/reflection_environment/ReflectionEnvironmentPass.h"
#include "passes/rt_ambient_occlusion/RTAmbientOcclusionPass.h"
#include "passes/rt_global_illumination/RTGlobalIlluminationPass.h"
#include "passes/rt_reflections/RTReflectionsPass.h"
#include "passes/rt_shadows/RTShadowsPass.h"
#include "passes/screen_space_oracle/ScreenSpaceOraclePass.h"
#include "passes/shadow_denoise/ShadowDenoisePass.h"
#include "passes/ssgi/SSGIPass.h"
#include "passes/ssr/SSRPass.h"
#include "passes/ssgi_denoise/SSGIDenoisePass.h"

namespace fp {

const PassRegistry& builtinPasses() {
    static const PassRegistry registry = [] {
        PassRegistry r;
        r.add<HZBPass>("hzb", "furthest and closest hierarchical Z of device depth (algorithms §2)");
        r.add<PrevColorReductionPass>(
            "prev_color_reduction",
            "previous-frame colour reprojected and reduced to 5 mips, leak-free (algorithms §3)");
        r.add<SSGIPass>("ssgi",
                        "screen-space diffuse indirect: cosine rays marched through the "
                        "HZB, last frame's colour at the hits, AO (algorithms §4)");
        r.add<SSGIDenoisePass>("ssgi_denoise",
                               "SSGI denoiser: 8-tap bilateral reconstruction and "
                               "temporal accumulation (algorithms §6.2)");
        r.add<DiffuseIndirectCompositePass>("diffuse_indirect_composite",
                                            "SceneColor × AO + diffuse albedo × SSGI, 4.27 or UE5 "
                                            "per shading model (algorithms §7)");
        r.add<RTShadowsPass>("rt_shadows",
                             "ray-traced shadows of one light through Embree "
                             "packets, subsurface transmission, light attenuation "
                             "(algorithms §9)");
        r.add<RTAmbientOcclusionPass>("rt_ambient_occlusion",
                                      "ray-traced ambient occlusion: cosine rays about the "
                                      "depth buffer's normal up to the AO radius, through "
                                      "Embree packets (algorithms §12.1)");
        r.add<RTReflectionsPass>("rt_reflections",
                                 "ray-traced reflections: mirror or GGX rays through Embree, hits "
                                 "lit by the scene's lights with shadow rays, the sky on a miss; "
                                 "SSR's output format (algorithms §12.4)");
        r.add<HybridPass>("hybrid",
                          "framepass's own: SSGI's rays marched on screen, those it cannot "
                          "finish traced through the scene and shaded as RTGI shades them "
                          "(algorithms §12.3)");
        r.add<HybridReflectionsPass>("hybrid_reflections",
                                     "framepass's own: SSR's rays marched and read on screen "
                                     "exactly as `ssr`, those the screen cannot finish traced "
                                     "through the scene and lit as rt_reflections lights its hits "
                                     "(algorithms §12.3)");
        r.add<RTGlobalIlluminationPass>("rt_global_illumination",
                                        "ray-traced diffuse global illumination, Unreal 4.27's "
                                        "brute force: cosine paths through Embree, the lights "
                                        "sampled at every hit (algorithms §12.2)");
        r.add<AODenoisePass>("ao_denoise",
                             "the AO denoiser after rt_ambient_occlusion: hit-distance-sized "
                             "bilateral reconstruction, pre-convolutions, temporal accumulation "
                             "(algorithms §12.5)");
        r.add<GIDenoisePass>("gi_denoise",
                             "the diffuse-and-AO denoiser after rt_global_illumination: "
                             "hit-distance-sized bilateral reconstruction, pre-convolution, "
                             "temporal accumulation (algorithms §12.5)");
        r.add<ReflectionDenoisePass>("reflection_denoise",
                                     "the reflection denoiser after rt_reflections: kernels the "
                                     "size of the reflected lobe, temporal accumulation "
                                     "(algorithms §12.5)");
        r.add<ShadowDenoisePass>("shadow_denoise",
                                 "penumbra-aware spatial shadow denoiser: blur "
                                 "radius from occluder distance and light size "
                                 "(algorithms §6.3)");
        r.add<DeferredLightingPass>(
            "deferred_lighting",
            "direct lighting of one light per shading model, shadowed by "
            "its light attenuation, added to scene colour (algorithms §9.6)");
        r.add<SSRPass>("ssr",
                       "screen-space reflections: mirror or GGX rays marched through the HZB as "
                       "SSGI's, last frame's colour at the reprojected hits (algorithms §5)");
        r.add<ReflectionEnvironmentPass>(
            "reflection_environment",
            "ReflectionEnvironment + SkyLighting: the sky light's SH diffuse, screen-space "
            "reflections then the prefiltered sky under specular occlusion, × EnvBRDF (algorithms §8)");
        r.add<CameraVelocityPass>("camera_velocity", "camera motion vectors: where each pixel's "
                                                     "surface was on last frame's screen");
        r.add<DisplayPass>("display",
                           "a buffer as a picture: the OpenColorIO view or Unreal 4.27's filmic tonemapper");
        r.add<ScreenSpaceOraclePass>(
            "screen_space_oracle",
            "framepass's own reference, not Unreal's: the best any screen-space method can do "
            "with this capture (many rays, half-pixel steps on full-resolution depth, no mips)");
        r.add<ErrorMeasurePass>("error_measure",
                                "error of any output against a reference (a "
                                "Truth.* layer): metrics in the report, heat map");
        // Cvars framepass knows but that no parameter emulates (parameters declare their own
        // cvars beside them, in their pass's paramSpec).
        r.recognise("r.SSGI.Enable", nullptr, "the SSGI chain is selected by the config's passes");
        r.recognise("r.DynamicGlobalIlluminationMethod", 2,
                    "UE5 GI method: framepass's chain is 2 (screen-space GI); Lumen (1) is not "
                    "emulated");
        r.recognise("r.AmbientOcclusion.Denoiser.PreConvolution.KernelSpreadFactor", 4,
                    "ao_denoise sizes its spatial stages from the rays' hit distance instead "
                    "(algorithms §12.5)");
        r.recognise("r.RayTracing.Shadows", 1,
                    "shadows are ray traced (rt_shadows) whenever the chain has the light step");
        r.recognise("r.RayTracing.Shadows.EnableTwoSidedGeometry", 1,
                    "shadow rays always see both sides of every triangle (Unreal's default)");
        r.recognise("r.RayTracing.Shadows.AcceptFirstHit", 0,
                    "rt_shadows tests occlusion with any hit and finds the closest hit only for "
                    "blocked rays whose distance the denoiser reads: the same result as Unreal's "
                    "default 0");
        return r;
    }();
    return registry;
}

}  // namespace fp
