#include "passes/deferred_lighting/DeferredLightingPass.h"

#include "foundation/PerPixel.h"
#include "foundation/Tiles.h"
#include "framework/PassPorts.h"
#include "passes/deferred_lighting/DeferredLightingKernel.h"
#include "passes/deferred_lighting/DeferredLightingLanes.h"
#include "screenspace/GBuffer.h"
#include "shading/NamedLight.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fp {

namespace {

using deferred_lighting::kAttenuation;
using deferred_lighting::kColor;

// A rect light's grid × grid cell centres (camera-relative, row j outer, column i inner) into
// `points`, and its emitter normal, cell area and point count into `shape`.
void rectGrid(const Light& light, int grid, deferred_lighting::LightShape& shape,
              std::vector<Vec3f>& points) {
    const Vec3f hu(light.halfU), hv(light.halfV);
    shape.rectNormal = normalize(cross(hu, hv));
    shape.rectCellArea = 4.0f * length(cross(hu, hv)) / float(grid * grid);
    points.clear();
    for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i)
            points.push_back(shape.position + hu * ((2.0f * i + 1.0f) / grid - 1.0f) +
                             hv * ((2.0f * j + 1.0f) / grid - 1.0f));
    shape.rectCount = int(points.size());
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

}  // namespace

deferred_lighting::LightShape DeferredLightingPass::lightShape(PassContext& ctx,
                                                              std::vector<Vec3f>& rectPoints) const {
    const CameraView& cam = ctx.frame().camera.current;
    const Light& light = namedLight(ctx.lights(), mParams.light);
    deferred_lighting::LightShape shape{};
    shape.type = light.type;
    shape.position = Vec3f(light.position - cam.position);
    shape.axis = normalize(Vec3f(light.direction));
    shape.color = light.color * light.intensity;
    shape.attenuationRadius = light.attenuationRadius;
    shape.cosOuter = light.cosOuterCone();
    shape.cosInner = light.cosInnerCone();
    if (light.type == LightType::Rect) rectGrid(light, mParams.rectSamples, shape, rectPoints);
    return shape;
}

void DeferredLightingPass::execute(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const Extent size = frame.extent;
    std::vector<Vec3f> rectPoints;
    const deferred_lighting::LightShape light = lightShape(ctx, rectPoints);
    const deferred_lighting::Frame f = deferred_lighting::bindFrame(
        HostPorts{ctx}, frame, light, rectPoints.data(), PreintegratedSkinLut::instance().view());
    // Only a rect light's grid is worth a vector: other lights have one direction a pixel, and
    // their per-pixel set-up (position, material, view) costs as much as their one BxDF (tried:
    // the same 82 ms at 1080p in lanes as one pixel at a time).
    const bool inLanes = mParams.lanes && light.type == LightType::Rect;
    const int lanes = inLanes ? deferred::lanes() : 1;
    using deferred_lighting::kCounterCount;

    std::array<std::atomic<uint64_t>, kCounterCount> totals{};
    forEachTile(size.width, size.height, [&](const Tile& t) {
        unsigned long long counts[kCounterCount] = {};
        for (int y = t.y0; y < t.y1; ++y) {
            if (!inLanes) {
                for (int x = t.x0; x < t.x1; ++x)
                    deferred_lighting::shadePixel(f, x, y, deferred_lighting::startPixel(f, x, y), counts);
                continue;
            }
            // Default-lit pixels of `lanes` neighbours share a vector; the others go one by one
            // through the scalar reference.
            for (int x0 = t.x0; x0 < t.x1; x0 += lanes) {
                deferred::PixelLanes group;
                int laneX[deferred::kMaxLanes];
                Vec3f laneColor[deferred::kMaxLanes];
                for (int x = x0; x < std::min(x0 + lanes, t.x1); ++x) {
                    const deferred_lighting::PixelStart s = deferred_lighting::startPixel(f, x, y);
                    if (!s.lit || !isDefaultLitLobe(s.model)) {
                        deferred_lighting::shadePixel(f, x, y, s, counts);
                        continue;
                    }
                    const int k = group.count++;
                    laneX[k] = x;
                    laneColor[k] = s.color;
                    const BxDFSurface m = deferred_lighting::materialAt(f, s.model, x, y);
                    const Vec3f V = normalize(-s.p);
                    put(group.px, group.py, group.pz, k, s.p);
                    put(group.vx, group.vy, group.vz, k, V);
                    put(group.nx, group.ny, group.nz, k, m.N);
                    put(group.diffuseR, group.diffuseG, group.diffuseB, k, m.diffuseColor);
                    put(group.specularR, group.specularG, group.specularB, k, m.specularColor);
                    group.roughness[k] = m.roughness;
                    deferred_lighting::shadowsAt(f, x, y, group.surfaceShadow[k], group.transmissionShadow[k]);
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
                deferred::shadeRectDefaultLit(f.light, group, sums);
                for (int k = 0; k < group.count; ++k) {
                    Vec3f c = laneColor[k];
                    if (!sums.reached[k]) {
                        ++counts[deferred_lighting::kSkipped];
                    } else {
                        ++counts[deferred_lighting::kLit];
                        c += Vec3f{sums.r[k], sums.g[k], sums.b[k]};
                    }
                    for (int ch = 0; ch < 3; ++ch) f.out[ch].at(laneX[k], y) = c[ch];
                }
            }
        }
        for (int i = 0; i < kCounterCount; ++i) totals[size_t(i)] += counts[i];
    });
    ctx.addWork("pixels", totals[deferred_lighting::kLit]);
    ctx.addWork("skippedPixels", totals[deferred_lighting::kSkipped]);
}

}  // namespace fp
