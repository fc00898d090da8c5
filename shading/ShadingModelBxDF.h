#pragma once
// Direct lighting of one decoded GBuffer pixel by one light, per shading model, as Unreal 4.27's
// deferred lights evaluate it (ShadingModels.ush, algorithms §9.6): a surface part (diffuse and
// specular, both already × NoL) and a transmission part that is not × NoL, because it models
// light arriving through the surface from the far side. The caller multiplies each term by the
// light's falloff colour and its own shadowing (the transmission term takes the subsurface
// shadow, algorithms §9.3).
#include "foundation/Math.h"

namespace fp {

/// One GBuffer pixel, decoded.
struct BxDFSurface {
    int shadingModel;                   //!< algorithms §1.6 ids (ShadingModelId)
    Vec3f N;                            //!< unit world normal
    Vec3f diffuseColor, specularColor;  //!< as SurfaceBRDF: BaseColor·(1 − Metallic), F0
    float roughness;                    //!< perceptual roughness [0, 1]
    Vec3f subsurfaceColor;              //!< CustomData.rgb² for 2, 3, 6; FuzzColor for cloth (8)
    float opacity;                      //!< CustomData.a for 2, 3, 6; cloth amount for 8
    float clearCoat = 0, clearCoatRoughness = 0;  //!< CustomData.r / .g for clear coat (4)
    float gbufferAO = 1;                          //!< GBuffer material AO [0, 1]
};

/// Each term per unit light falloff colour (irradiance at normal incidence); the surface terms
/// already carry NoL, the transmission term does not.
struct BxDFTerms {
    Vec3f diffuse, specular, transmission;
};

/// Reflected (diffuse, specular) and transmitted radiance towards unit V from a light in unit
/// direction L. Zero surface terms when L is below the surface (N·L ≤ 0); always finite, also for
/// V at or below the horizon.
BxDFTerms evaluateBxDF(const BxDFSurface& s, const Vec3f& V, const Vec3f& L);

/// True for the shading models evaluateBxDF lights with the default-lit lobe alone (no
/// transmission, no lobe of their own): what deferred_lighting's SIMD lanes may shade.
bool isDefaultLitLobe(int model);

}  // namespace fp
