#include "passes/deferred_lighting/DeferredLightingPass.h"

#include "screenspace/GBuffer.h"
#include "foundation/ShadingModel.h"
#include "foundation/Tiles.h"
#include "passes/deferred_lighting/DeferredLightingLanes.h"
#include "shading/BRDF.h"
#include "shading/LightAttenuation.h"
#include "shading/NamedLight.h"
#include "shading/ShadingModelBxDF.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

constexpr const char* kColor = "color";
constexpr const char* kAttenuation = "attenuation";

// One direction towards the light with the unshadowed irradiance it brings at normal incidence.
struct Incoming {
    Vec3f L, falloff;
};

// The light, relative to the eye so a camera far from the origin loses nothing.
struct LightGeometry {
    const Light& light;
    Vec3f position, axis, color;
    deferred::RectGrid rect;  // rect lights: the grid of points that integrates the area
};

// A rect light's grid × grid cell centres, emitter normal and cell area.
deferred::RectGrid rectGrid(const Light& light, const Vec3f& position, const Vec3f& color,
                            int grid) {
    deferred::RectGrid g;
    const Vec3f hu(light.halfU), hv(light.halfV);
    g.normal = normalize(cross(hu, hv));
    g.cellArea = 4.0f * length(cross(hu, hv)) / float(grid * grid);
    g.color = color;
    for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i)
            g.points.push_back(position + hu * ((2.0f * i + 1.0f) / grid - 1.0f) +
                               hv * ((2.0f * j + 1.0f) / grid - 1.0f));
    return g;
}

// The light's unshadowed contributions at p: one direction, or the rect light's grid points in
// front of the emitter. Returns how many were written to `in` (0: out of the light's reach).
int incomingLight(const LightGeometry& g, const Vec3f& p, Incoming* in) {
    const Light& light = g.light;
    if (light.type == LightType::Directional) {
        in[0] = {-g.axis, g.color};
        return 1;
    }
    if (light.type == LightType::Rect) {
        int n = 0;
        for (const Vec3f& q : g.rect.points) {
            const Vec3f d = q - p;
            const float dist2 = dot(d, d);
            const Vec3f L = d / std::sqrt(dist2);
            const float cosL = -dot(L, g.rect.normal);
            if (cosL <= 0.0f)
                continue;
            in[n++] = {L, g.color * (cosL * g.rect.cellArea / dist2)};
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
        // algorithms §1.7: subsurface-type colours are stored as √colour.
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
// by the surface shadow, transmission by the transmission shadow (algorithms §9.5).
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
    s.add("lanes", &Params::lanes,
          "rect lights: default-lit pixels a SIMD vector at a time (false: the scalar reference; "
          "same bits)");
    return s;
}

PassIO DeferredLightingPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::sceneColorInput(kColor, "scene colour the light adds into"),
        {.name = kAttenuation,
         .channels = {"R", "G", "B", "A"},
         .optional = true,
         .doc = "light attenuation (algorithms §9.5) from rt_shadows or shadow_denoise; unbound = "
                "unshadowed"},
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::baseColorInput(),
        gbuffer::metallicInput("GBufferB.r"),
        gbuffer::specularInput("GBufferB.g"),
        gbuffer::roughnessInput("GBufferB.b"),
        gbuffer::shadingModelInput("picks the BxDF; unlit and sky pixels are skipped"),
        gbuffer::customDataInput("per shading model (algorithms §1.7)", true),
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

namespace {

// Lane k of three structure-of-arrays planes.
void put(float* x, float* y, float* z, int k, const Vec3f& v) {
    x[k] = v.x;
    y[k] = v.y;
    z[k] = v.z;
}

// One pixel as both paths start it: its scene colour and, on a lit surface, its model and
// camera-relative position.
struct PixelStart {
    Vec3f color;
    bool lit = false;
    int model = 0;
    Vec3f p;
};

}  // namespace

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
                                  ctx.input(gbuffer::kSpecular)->image().plane(0),
                                  ctx.input(gbuffer::kRoughness)->image().plane(0),
                                  ctx.input(gbuffer::kCustomData),
                                  ctx.input(gbuffer::kGBufferAO)};
    Image& out = ctx.output(kColor, {size}).image();

    const int grid = mParams.rectSamples;
    const Vec3f position(light.position - cam.position), color(light.color * light.intensity);
    const LightGeometry geometry{
        light, position, normalize(Vec3f(light.direction)), color,
        light.type == LightType::Rect ? rectGrid(light, position, color, grid)
                                      : deferred::RectGrid{}};
    // Only a rect light's grid is worth a vector: other lights have one direction a pixel, and
    // their per-pixel set-up (position, material, view) costs as much as their one BxDF (tried:
    // the same 82 ms at 1080p in lanes as one pixel at a time).
    const bool inLanes = mParams.lanes && light.type == LightType::Rect;
    const int lanes = inLanes ? deferred::lanes() : 1;

    const auto start = [&](int x, int y) {
        PixelStart s;
        s.color = {sceneColor.plane(0).at(x, y), sceneColor.plane(1).at(x, y),
                   sceneColor.plane(2).at(x, y)};
        const double d = depth.at(x, y);
        s.model = truncToInt(models.at(x, y), 0, 255);
        s.lit = isLitSurface(d, models.at(x, y));
        if (s.lit)
            s.p = Vec3f(cam.translatedFromPixel(x, y, d));
        return s;
    };
    const auto shadows = [&](int x, int y, float& surfaceShadow, float& transmissionShadow) {
        surfaceShadow = transmissionShadow = 1.0f;
        if (attenuation) {
            const LightAttenuation la = LightAttenuation::load(attenuation->image(), x, y);
            surfaceShadow = la.surfaceShadow(light.type);
            transmissionShadow = la.transmissionShadow(light.type);
        }
    };
    const auto store = [&](int x, int y, const Vec3f& c) {
        for (int ch = 0; ch < 3; ++ch)
            out.plane(ch).at(x, y) = c[ch];
    };

    forEachTile(size.width, size.height, [&](const Tile& t) {
        std::vector<Incoming> in(std::max<std::size_t>(1, geometry.rect.points.size()));
        uint64_t pixels = 0, skipped = 0;
        // The scalar reference: every pixel, every model.
        const auto shadeOne = [&](int x, int y, PixelStart s) {
            const int n = s.lit ? incomingLight(geometry, s.p, in.data()) : 0;
            if (n == 0) {
                ++skipped;  // sky, unlit, or out of the light's reach: colour unchanged
            } else {
                ++pixels;
                float surfaceShadow, transmissionShadow;
                shadows(x, y, surfaceShadow, transmissionShadow);
                s.color += reflectedLight(materialAt(material, s.model, x, y), s.p, in.data(), n,
                                          surfaceShadow, transmissionShadow);
            }
            store(x, y, s.color);
        };
        for (int y = t.y0; y < t.y1; ++y) {
            if (!inLanes) {
                for (int x = t.x0; x < t.x1; ++x)
                    shadeOne(x, y, start(x, y));
                continue;
            }
            // Default-lit pixels of `lanes` neighbours share a vector; the others go one by one.
            for (int x0 = t.x0; x0 < t.x1; x0 += lanes) {
                deferred::PixelLanes group;
                int laneX[deferred::kMaxLanes];
                Vec3f laneColor[deferred::kMaxLanes];
                for (int x = x0; x < std::min(x0 + lanes, t.x1); ++x) {
                    const PixelStart s = start(x, y);
                    if (!s.lit || !isDefaultLitLobe(s.model)) {
                        shadeOne(x, y, s);
                        continue;
                    }
                    const int k = group.count++;
                    laneX[k] = x;
                    laneColor[k] = s.color;
                    const BxDFSurface m = materialAt(material, s.model, x, y);
                    const Vec3f V = normalize(-s.p);
                    put(group.px, group.py, group.pz, k, s.p);
                    put(group.vx, group.vy, group.vz, k, V);
                    put(group.nx, group.ny, group.nz, k, m.N);
                    put(group.diffuseR, group.diffuseG, group.diffuseB, k, m.diffuseColor);
                    put(group.specularR, group.specularG, group.specularB, k, m.specularColor);
                    group.roughness[k] = m.roughness;
                    shadows(x, y, group.surfaceShadow[k], group.transmissionShadow[k]);
                }
                if (group.count == 0)
                    continue;
                // Lanes past the count repeat the first pixel: finite work, results unread.
                for (int k = group.count; k < lanes; ++k)
                    for (float* a : {group.px, group.py, group.pz, group.vx, group.vy, group.vz,
                                     group.nx, group.ny, group.nz, group.diffuseR, group.diffuseG,
                                     group.diffuseB, group.specularR, group.specularG,
                                     group.specularB, group.roughness, group.surfaceShadow,
                                     group.transmissionShadow})
                        a[k] = a[0];
                deferred::LaneSums sums;
                deferred::shadeRectDefaultLit(geometry.rect, group, sums);
                for (int k = 0; k < group.count; ++k) {
                    Vec3f c = laneColor[k];
                    if (!sums.reached[k]) {
                        ++skipped;
                    } else {
                        ++pixels;
                        c += Vec3f{sums.r[k], sums.g[k], sums.b[k]};
                    }
                    store(laneX[k], y, c);
                }
            }
        }
        ctx.addWork("pixels", pixels);
        ctx.addWork("skippedPixels", skipped);
    });
}

}  // namespace fp
