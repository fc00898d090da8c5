#include "passes/deferred_lighting/DeferredLightingPass.h"

#include "passes/common/GBuffer.h"
#include "passes/core/ShadingModel.h"
#include "passes/core/Tiles.h"
#include "passes/lighting/BRDF.h"
#include "passes/lighting/LightAttenuation.h"
#include "passes/lighting/NamedLight.h"
#include "passes/lighting/ShadingModelBxDF.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kColor = "color";
constexpr const char* kAttenuation = "attenuation";
constexpr const char* kSpecular = "specular";
constexpr const char* kRoughness = "roughness";

// One direction towards the light with the unshadowed irradiance it brings at normal incidence.
struct Incoming {
    Vec3f L, falloff;
};

// The light, relative to the eye so a camera far from the origin loses nothing.
struct LightGeometry {
    const Light& light;
    Vec3f position, axis, color;
    int grid;  // rect lights: grid × grid points
};

// The light's unshadowed contributions at p: one direction, or a grid over a rect light. Returns
// how many were written to `in` (0: out of the light's reach).
int incomingLight(const LightGeometry& g, const Vec3f& p, Incoming* in) {
    const Light& light = g.light;
    if (light.type == LightType::Directional) {
        in[0] = {-g.axis, g.color};
        return 1;
    }
    if (light.type == LightType::Rect) {
        const int grid = g.grid;
        const Vec3f hu(light.halfU), hv(light.halfV);
        const Vec3f nl = normalize(cross(hu, hv));
        const float cellArea = 4.0f * length(cross(hu, hv)) / float(grid * grid);
        int n = 0;
        for (int j = 0; j < grid; ++j)
            for (int i = 0; i < grid; ++i) {
                const Vec3f q = g.position + hu * ((2.0f * i + 1.0f) / grid - 1.0f) +
                                hv * ((2.0f * j + 1.0f) / grid - 1.0f);
                const Vec3f d = q - p;
                const float dist2 = dot(d, d);
                const Vec3f L = d / std::sqrt(dist2);
                const float cosL = -dot(L, nl);
                if (cosL <= 0.0f)
                    continue;
                in[n++] = {L, g.color * (cosL * cellArea / dist2)};
            }
        return n;
    }
    const Vec3f d = g.position - p;
    const float dist2 = dot(d, d);
    if (light.attenuationRadius > 0.0 && dist2 > light.attenuationRadius * light.attenuationRadius)
        return 0;
    const Vec3f L = d / std::sqrt(dist2);
    // Inverse square, as the capture and the truth light it.
    const float falloff = light.spotMask(dot(-L, g.axis)) / dist2;
    if (falloff <= 0.0f)
        return 0;
    in[0] = {L, g.color * falloff};
    return 1;
}

// The GBuffer planes the BxDF reads.
struct MaterialInputs {
    const Image& normal;
    const Image& baseColor;
    const Plane& metallic;
    const Plane& specular;
    const Plane& roughness;
    const Texture* customData;
    const Texture* gbufferAO;
};

// The BxDF inputs of pixel (x, y) from its GBuffer.
BxDFSurface materialAt(const MaterialInputs& m, int model, int x, int y) {
    BxDFSurface s{};
    s.shadingModel = model;
    s.N = normalize(gbuffer::worldNormalAt(m.normal, x, y));
    const Vec3f base{m.baseColor.plane(0).at(x, y), m.baseColor.plane(1).at(x, y),
                     m.baseColor.plane(2).at(x, y)};
    const SurfaceBRDF brdf = SurfaceBRDF::fromMaterial(base, m.metallic.at(x, y),
                                                       m.specular.at(x, y), m.roughness.at(x, y));
    s.diffuseColor = brdf.diffuseColor;
    s.specularColor = brdf.specularColor;
    s.roughness = brdf.roughness;
    if (m.customData) {
        // Reference §1.7: subsurface-type colours are stored as √colour.
        const Image& cd = m.customData->image();
        const float r = cd.plane(0).at(x, y), g = cd.plane(1).at(x, y), b = cd.plane(2).at(x, y),
                    a = cd.plane(3).at(x, y);
        s.subsurfaceColor = {r * r, g * g, b * b};
        s.opacity = a;
        s.clearCoat = r;
        s.clearCoatRoughness = g;
    }
    s.gbufferAO = m.gbufferAO ? m.gbufferAO->image().plane(0).at(x, y) : 1.0f;
    return s;
}

// The light reflected and transmitted towards the eye at camera-relative p: surface terms dimmed
// by the surface shadow, transmission by the transmission shadow (reference §9.5).
Vec3f reflectedLight(const BxDFSurface& s,
                     const Vec3f& p,
                     const Incoming* in,
                     int n,
                     float surfaceShadow,
                     float transmissionShadow) {
    const Vec3f V = normalize(-p);
    Vec3f sum;
    for (int k = 0; k < n; ++k) {
        const BxDFTerms b = evaluateBxDF(s, V, in[k].L);
        sum += ((b.diffuse + b.specular) * surfaceShadow + b.transmission * transmissionShadow) *
               in[k].falloff;
    }
    return sum;
}

}  // namespace

ParamSpec<DeferredLightingParams> DeferredLightingPass::paramSpec() {
    ParamSpec<DeferredLightingParams> s;
    s.add("light", &Params::light, "name of the light (\"\" = the scene's only light)");
    s.add("rectSamples", &Params::rectSamples,
          "rect lights: an N×N grid of points integrates the light's area")
        .range(1, 16);
    return s;
}

PassIO DeferredLightingPass::describe() const {
    PassIO io;
    io.inputs = {
        {.name = kColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .captureDefault = "SceneColor",
         .doc = "scene colour the light adds into"},
        {.name = kAttenuation,
         .channels = {"R", "G", "B", "A"},
         .optional = true,
         .doc = "light attenuation (reference §9.5) from rt_shadows or shadow_denoise; unbound = "
                "unshadowed"},
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::baseColorInput(),
        gbuffer::metallicInput("GBufferB.r"),
        {.name = kSpecular, .channels = {"Y"}, .captureDefault = "Specular", .doc = "GBufferB.g"},
        {.name = kRoughness, .channels = {"Y"}, .captureDefault = "Roughness", .doc = "GBufferB.b"},
        gbuffer::shadingModelInput("picks the BxDF; unlit and sky pixels are skipped"),
        gbuffer::customDataInput("per shading model (reference §1.7)", true),
        gbuffer::gbufferAOInput(true),
    };
    io.outputs = {
        {.name = kColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "scene colour + this light"},
    };
    io.needsCamera = true;
    io.needsLights = true;  // the light
    return io;
}

void DeferredLightingPass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const CameraView& cam = frame.camera.current;
    const Light& light = namedLight(ctx.lights(), mParams.light);
    const Extent size = frame.extent;
    const Image& sceneColor = ctx.input(kColor)->image();
    const Texture* attenuation = ctx.input(kAttenuation);
    const Plane& depth = ctx.input(gbuffer::kDepth)->image().plane(0);
    const Plane& models = ctx.input(gbuffer::kShadingModel)->image().plane(0);
    const MaterialInputs material{ctx.input(gbuffer::kNormal)->image(),
                                  ctx.input(gbuffer::kBaseColor)->image(),
                                  ctx.input(gbuffer::kMetallic)->image().plane(0),
                                  ctx.input(kSpecular)->image().plane(0),
                                  ctx.input(kRoughness)->image().plane(0),
                                  ctx.input(gbuffer::kCustomData),
                                  ctx.input(gbuffer::kGBufferAO)};
    Image& out = ctx.output(kColor, {size}).image();

    const int grid = mParams.rectSamples;
    const LightGeometry geometry{light, Vec3f(light.position - cam.position),
                                 normalize(Vec3f(light.direction)), light.color * light.intensity,
                                 grid};

    forEachTile(size.width, size.height, [&](const Tile& t) {
        std::vector<Incoming> in(std::size_t(std::max(1, grid * grid)));
        uint64_t pixels = 0, skipped = 0;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                Vec3f c{sceneColor.plane(0).at(x, y), sceneColor.plane(1).at(x, y),
                        sceneColor.plane(2).at(x, y)};
                const double d = depth.at(x, y);
                const int model = truncToInt(models.at(x, y), 0, 255);
                const bool lit = isLitSurface(d, models.at(x, y));
                const Vec3f p = lit ? Vec3f(cam.translatedFromPixel(x, y, d)) : Vec3f{};
                const int n = lit ? incomingLight(geometry, p, in.data()) : 0;
                if (n == 0) {
                    ++skipped;  // sky, unlit, or out of the light's reach: colour unchanged
                } else {
                    ++pixels;
                    float surfaceShadow = 1.0f, transmissionShadow = 1.0f;
                    if (attenuation) {
                        const LightAttenuation la =
                            LightAttenuation::load(attenuation->image(), x, y);
                        surfaceShadow = la.surfaceShadow(light.type);
                        transmissionShadow = la.transmissionShadow(light.type);
                    }
                    c += reflectedLight(materialAt(material, model, x, y), p, in.data(), n,
                                        surfaceShadow, transmissionShadow);
                }
                for (int ch = 0; ch < 3; ++ch)
                    out.plane(ch).at(x, y) = c[ch];
            }
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", skipped);
    });
}

}  // namespace fp
