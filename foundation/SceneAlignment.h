#pragma once
// Does a scene line up with a capture? The camera rays of a grid of the capture's surface pixels
// are traced through the scene and where they hit is compared with the capture's depth. A scene
// in other units, seen from another camera or simply another scene disagrees on most pixels;
// the ray-traced passes would then trace against the wrong geometry and, silently, light nothing.
#include "foundation/Camera.h"
#include "foundation/Image.h"
#include "foundation/RayScene.h"

#include <string>

namespace fp {

struct SceneAlignment {
    int sampled = 0;   //!< surface pixels (finite depth) whose camera ray was traced
    int agreeing = 0;  //!< of them, hits within kDepthTolerance of the capture's depth
    int missed = 0;    //!< of them, rays that hit nothing
    /// Median over the hits of the capture's depth over the traced depth: 1 when aligned, a
    /// constant factor (0.01, 100) when the scene is in other units. 0 without hits.
    double medianDepthRatio = 0;
    /// Fraction of the hits whose ratio is within 5 % of the median: high with a units factor
    /// (every depth off by the same factor), low for another camera or scene.
    double ratioConsistency = 0;
    /// The factor the scene was scaled by (about the world origin) for this measurement.
    double scale = 1;

    /// Relative depth difference under which a traced hit agrees with the capture: generous
    /// against sub-pixel edges and a capture's half-float depth (11-bit mantissa), far below
    /// what a wrong scene gives.
    static constexpr double kDepthTolerance = 0.02;
    double agreeingFraction() const { return sampled > 0 ? double(agreeing) / sampled : 1.0; }
};

/// Traces the camera ray of every `step`-th pixel in x and y with finite depth in `sceneDepth`
/// (view depth, scene units) through `scene` scaled by `scale` about the world origin (traced as
/// the unscaled scene from the eye / scale) and compares the hits' view depth with it.
SceneAlignment measureSceneAlignment(const RayScene& scene, const CameraView& camera,
                                     const Image& sceneDepth, int step, double scale = 1.0);

/// Of the unit factors between common scene units (powers of ten from mm to km, inches, feet),
/// the scale at which the scene lines up best, measured at `step`; scale 1 when none is better
/// than the scene as it is. A scene in other units than its capture is found this way even when
/// the camera, in the capture's units, sees none of it unscaled.
SceneAlignment bestUnitScale(const RayScene& scene, const CameraView& camera,
                             const Image& sceneDepth, int step);

/// The grid step that samples about `rays` pixels of a width × height frame.
int alignmentStep(int width, int height, int rays = 4096);

/// One paragraph on what a misalignment `a` most likely is (units, camera, another scene), naming
/// the setting to change. `units`: the best unit scale (bestUnitScale); `unitsToDeclare`: the
/// scene's "sceneUnitsPerMeter" that would apply that scale.
std::string describeMisalignment(const SceneAlignment& a, const SceneAlignment& units,
                                 double unitsToDeclare);

}  // namespace fp
