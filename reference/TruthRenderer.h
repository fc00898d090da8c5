#pragma once
// Renders the truth layers of a capture (docs/captures.md and docs/design.md, Truth and evaluation) with the reference path tracer, for
// the same pixels and camera as the GBuffer: one primary ray through each pixel centre, then
// `spp` independent samples per pixel. Every layer comes with a `.StdErr` layer, the standard
// error of its per-pixel mean, so a comparison can tell when the reference itself is the limit.
//
//   Truth.DiffuseIndirectOneBounce  RGB  cosine-weighted mean of the radiance arriving from other
//                                        surfaces, each holding emission + direct light (what
//                                        SSGI reads from last frame's colour; algorithms §4.8:
//                                        irradiance/π, so DiffuseColor × this = indirect diffuse)
//   Truth.DiffuseIndirectFull       RGB  the same with every bounce
//   Truth.AO                        Y    fraction of cosine-distributed rays that travel further
//                                        than the AO radius (1 = open, 0 = enclosed): what
//                                        Unreal's ray-traced AO estimates at that radius
//   Truth.AOAnyDistance             Y    fraction of the same rays that hit nothing at any
//                                        distance: what SSGI's AO (1 − its rays' hit fraction,
//                                        however far the hit) estimates where it sees everything
//   Truth.Specular                  RGB  indirect specular radiance reflected to the camera by
//                                        the pixel's GGX lobe (Unreal's F·D·Vis), all bounces
//   Truth.ReflectedEmitter          Y    fraction of the same lobe's rays whose first hit is an
//                                        emitting surface (a light's visible shape or an emissive
//                                        material): where a screen-space reflection, which reads
//                                        the lit colour, shows a light the truth counts as that
//                                        light's own specular (compare --mask reflected-emitter)
//   Truth.Combined                  RGB  the path-traced beauty: emission + direct light of every
//                                        light (diffuse and specular) + DiffuseColor ×
//                                        DiffuseIndirectFull + Specular; what a whole chain's
//                                        final frame approximates
//   Truth.Shadow.<light>            Y    visibility of each light, averaged over its extent
//
// A scene's sky light (Scene::environment) lights every truth: a ray that leaves the scene
// receives its radiance, as direct light (so it is in the one-bounce layer too) and after any
// number of bounces. The backdrop the camera sees (Scene::skyColor) lights nothing.
//
// Every light is counted once: a mesh that is a light's visible shape (Mesh::shapeOf) shows its
// emission to the camera (in SceneColor and Truth.Combined) but adds nothing to the indirect
// layers, because the light it sends out is the light's own direct light. Sky pixels hold 0 in
// every layer.
#include "foundation/Camera.h"
#include "foundation/Image.h"
#include "foundation/Scene.h"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace fp {

struct TruthSettings {
    int64_t frame = 1;        //!< absolute frame number (seeds every pixel's samples)
    int samplesPerPixel = 256;
    double aoRadius = 100.0;  //!< scene units
    int maxBounces = 256;
};

struct TruthResult {
    std::map<std::string, Image> layers;  //!< "Truth.<Name>" and "Truth.<Name>.StdErr"
    std::vector<std::string> names;       //!< the truth layers in order, without .StdErr
    uint64_t rays = 0;
};

class TruthRenderer {
public:
    TruthRenderer(const Scene& scene, const FrameCamera& camera, const TruthSettings& settings)
        : mScene(scene), mCamera(camera), mSettings(settings) {}

    /// `progress(done, total)` is called (from worker threads, serialised) as tiles finish.
    TruthResult render(const std::function<void(int, int)>& progress = {}) const;

    /// The layer name of each light's shadow truth: Truth.Shadow.<id> (lightIdentifiers).
    static std::vector<std::string> shadowLayerNames(const Scene& scene);

private:
    const Scene& mScene;
    const FrameCamera& mCamera;
    TruthSettings mSettings;
};

}  // namespace fp
