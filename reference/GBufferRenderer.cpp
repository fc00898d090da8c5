#include "reference/GBufferRenderer.h"

#include "shading/DirectLighting.h"
#include "foundation/RayScene.h"
#include "foundation/Random.h"
#include "framework/SemanticBuffers.h"
#include "foundation/Tiles.h"

#include <atomic>
#include <cmath>
#include <limits>

namespace fp {

namespace {

constexpr uint32_t kSeedCurrent = 0x43415054u;   // "CAPT"
constexpr uint32_t kSeedPrevious = 0x50524556u;  // "PREV"
constexpr float kInf = std::numeric_limits<float>::infinity();

struct ShadedHit {
    bool hit = false;
    double depth = 0;  // view z
    Vec3d offset;      // hit point relative to the RayScene origin
    Vec3f color;     // emission + direct lighting
    Vec3f emission;
    RayHit ray;
    Vec3f normal;
};

// Traces the primary ray of pixel (px, py) of `cam` and shades it.
ShadedHit tracePixel(const RayScene& rs, const CameraView& cam, const Vec3f& eyeOffset, int px,
                     int py, const DirectLighting& lighting, Rng& rng, uint64_t& shadowRays) {
    ShadedHit out;
    const Vec3d dirD = cam.rayDirection(px, py);
    const Vec3f dir(dirD);
    out.ray = rs.intersect(eyeOffset, dir, 0.0f, kInf);
    if (!out.ray.hit) {
        // The backdrop plus the sky light, as a sky sphere shows it in Unreal: emissive, so a lit
        // chain that starts from Emissive shows it too.
        out.color = out.emission = rs.scene().skyColor + rs.scene().environment.sky.radiance(dir);
        return out;
    }
    out.hit = true;
    out.offset = Vec3d(eyeOffset) + dirD * double(out.ray.t);
    out.depth = dot(dirD, cam.forward) * double(out.ray.t);
    const SurfacePoint sp = surfaceAt(rs, out.ray, eyeOffset, dir);
    out.normal = sp.normal;
    out.emission = sp.emission;
    out.color = sp.emission + lighting.shade(sp, rng, shadowRays);
    return out;
}

bool usesCustomData(int model) { return model >= 2 && model <= 9; }

}  // namespace

CaptureResult GBufferRenderer::render() const {
    const CameraView& cam = mCamera.current;
    const CameraView& prev = mCamera.previous ? *mCamera.previous : cam;
    const int W = cam.width, H = cam.height;
    // Geometry relative to this frame's eye: every per-pixel quantity is a small number.
    const RayScene rs(mScene, cam.position);
    const DirectLighting lighting(rs, mSettings.lightSamples);
    const Vec3f prevEye(prev.position - cam.position);

    CaptureResult result;
    for (const auto& b : semanticBuffers()) {
        if (std::string(b.name) == "GBufferAO") {
            result.buffers[b.name] = Image(W, H, b.channels, 1.0f);
            continue;
        }
        result.buffers[b.name] = Image(W, H, b.channels);
    }
    auto& B = result.buffers;
    std::atomic<uint64_t> shadowRays{0};

    forEachTile(W, H, [&](const Tile& t) {
        uint64_t rays = 0;
        for (int py = t.y0; py < t.y1; ++py)
            for (int px = t.x0; px < t.x1; ++px) {
                Rng rng(mSettings.frame, px, py, kSeedCurrent);
                const ShadedHit h = tracePixel(rs, cam, Vec3f{}, px, py, lighting, rng, rays);
                for (int c = 0; c < 3; ++c) {
                    B["SceneColor"].plane(c).at(px, py) = h.color[c];
                    B["Emissive"].plane(c).at(px, py) = h.emission[c];
                }

                // Velocity: where this pixel's surface (or, for sky, its direction) was last frame.
                const Vec3d p = h.hit ? h.offset : cam.rayDirection(px, py) * 1e12;
                const auto proj = prev.projectOffset(p, cam.position);
                B["Velocity"].plane(0).at(px, py) = float(proj.px - (px + 0.5));
                B["Velocity"].plane(1).at(px, py) = float(proj.py - (py + 0.5));

                // Last frame, through the previous camera (the TAA history of a converged
                // accumulation of a static frame is that same colour).
                Rng prevRng(mSettings.frame - 1, px, py, kSeedPrevious);
                const ShadedHit ph = tracePixel(rs, prev, prevEye, px, py, lighting, prevRng, rays);
                for (int c = 0; c < 3; ++c) {
                    B["PrevSceneColor"].plane(c).at(px, py) = ph.color[c];
                    B["TAAHistory"].plane(c).at(px, py) = ph.color[c];
                }
                B["PrevSceneDepth"].plane(0).at(px, py) = ph.hit ? float(ph.depth) : kInf;

                if (!h.hit) {
                    B["SceneDepth"].plane(0).at(px, py) = kInf;
                    continue;  // sky: unlit, every other buffer stays 0
                }
                const Material& m = rs.material(h.ray);
                B["SceneDepth"].plane(0).at(px, py) = float(h.depth);
                for (int c = 0; c < 3; ++c) {
                    B["WorldNormal"].plane(c).at(px, py) = h.normal[c];
                    B["BaseColor"].plane(c).at(px, py) = m.baseColor[c];
                }
                B["Metallic"].plane(0).at(px, py) = m.metallic;
                B["Specular"].plane(0).at(px, py) = m.specular;
                B["Roughness"].plane(0).at(px, py) = m.roughness;
                B["ShadingModel"].plane(0).at(px, py) = float(m.shadingModel);
                B["Opacity"].plane(0).at(px, py) = m.opacity;
                B["InstanceId"].plane(0).at(px, py) = float(rs.mesh(h.ray).instanceId);
                if (usesCustomData(m.shadingModel)) {
                    // algorithms §1.7: subsurface-type models store √colour and opacity; clear
                    // coat stores its amount and roughness.
                    float cd[4] = {std::sqrt(m.subsurfaceColor.x), std::sqrt(m.subsurfaceColor.y),
                                   std::sqrt(m.subsurfaceColor.z), m.opacity};
                    if (m.shadingModel == 4) {
                        cd[0] = m.clearCoat;
                        cd[1] = m.clearCoatRoughness;
                        cd[2] = cd[3] = 0.0f;
                    }
                    for (int c = 0; c < 4; ++c) B["CustomData"].plane(c).at(px, py) = cd[c];
                }
            }
        shadowRays += rays;
    });
    result.primaryRays = uint64_t(W) * H * 2;
    result.shadowRays = shadowRays;
    return result;
}

}  // namespace fp
