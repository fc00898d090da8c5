#pragma once
// The light that comes from far away: Unreal's sky light (algorithms §8.1–8.3), as the scene JSON
// gives it, a constant colour or a lat-long (equirectangular) radiance map, times an intensity.
// The reflection passes light with it; the truth tracer gives its radiance to every ray that
// leaves the scene, so both see the same sky. Data only: io/ reads the map into `latLong`.
#include "foundation/Image.h"
#include "foundation/Math.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace fp {

/// Which world axis is "up" in a lat-long map's frame.
enum class LatLongUp { Y, Z };

struct SkyLight {
    bool enabled = false;
    Vec3f color{1, 1, 1};   //!< constant radiance, or a tint on the map
    float intensity = 1.0f;
    Vec3f occlusionTint{0, 0, 0};  //!< what occluded sky diffuse turns into (Unreal's OcclusionTint)
    /// Scene-linear RGB lat-long map (empty: the sky is `color` everywhere). Row 0 is the zenith;
    /// u = 0.5 + atan2(up-frame y, −x)/(2π) as Blender's equirectangular environment maps it.
    Image latLong;
    LatLongUp up = LatLongUp::Y;
    std::string source;  //!< the map's file, for reports ("" for a constant sky)

    /// The map's (u, v) ∈ [0, 1]² of world direction `d` (unit). With up = Y (glTF's axes, as
    /// Blender exports them) Blender's (x, y, z) is (x, −z, y) here, so a Blender HDRI lands as it
    /// lights the Blender scene.
    static void latLongCoordinates(const Vec3f& d, LatLongUp up, float& u, float& v) {
        const float bx = d.x, by = up == LatLongUp::Y ? -d.z : d.y, bz = up == LatLongUp::Y ? d.y : d.z;
        u = 0.5f + std::atan2(by, -bx) / (2.0f * kPiF);
        v = 0.5f - std::asin(std::clamp(bz, -1.0f, 1.0f)) / kPiF;  // 0 at the zenith row
    }

    /// Radiance arriving from direction `d` (unit, pointing away from the scene towards the sky).
    Vec3f radiance(const Vec3f& d) const {
        if (!enabled) return {};
        const Vec3f tint = color * intensity;
        if (latLong.width() == 0) return tint;
        float u, v;
        latLongCoordinates(d, up, u, v);
        // Bilinear, wrapping in u (longitude) and clamping in v (the poles).
        const int w = latLong.width(), h = latLong.height();
        const float x = u * w - 0.5f, y = std::clamp(v * h - 0.5f, 0.0f, float(h - 1));
        const int x0 = int(std::floor(x)), y0 = std::min(int(y), h - 1), y1 = std::min(y0 + 1, h - 1);
        const float fx = x - float(x0), fy = y - float(y0);
        const int xa = ((x0 % w) + w) % w, xb = (xa + 1) % w;
        Vec3f c;
        for (int ch = 0; ch < 3; ++ch) {
            const Plane& p = latLong.plane(std::min(ch, latLong.channelCount() - 1));
            const float top = p.at(xa, y0) * (1 - fx) + p.at(xb, y0) * fx;
            const float bottom = p.at(xa, y1) * (1 - fx) + p.at(xb, y1) * fx;
            (ch == 0 ? c.x : ch == 1 ? c.y : c.z) = top * (1 - fy) + bottom * fy;
        }
        return c * tint;
    }
};

/// Unreal's reflection capture actor (algorithms §8.3): a cubemap of the scene seen from
/// `position`, used for the reflections of points inside its influence, with parallax against
/// its sphere or box. The faces are the radiance itself (io/ reads them from an EXR, or the
/// session renders them from the scene); reflection_environment prefilters them.
struct ReflectionCapture {
    enum class Shape { Sphere, Box };
    std::string name;
    Shape shape = Shape::Sphere;
    Vec3d position;          //!< world, scene units
    double radius = 0;       //!< sphere: influence radius (box: |extent|, its sort key)
    Vec3d extent;            //!< box: half size along world x, y, z (axis-aligned)
    double transitionDistance = 0;  //!< box: the fade band at its faces, scene units
    float brightness = 1.0f;
    Vec3d offset;            //!< Unreal's CaptureOffset: subtracted from the lookup vector
    /// Six square faces stacked top to bottom in the order +X, −X, +Y, −Y, +Z, −Z (OpenGL's
    /// axes), RGB; empty until read or rendered.
    Image faces;
    std::string source;      //!< the faces' EXR ("" when rendered from the scene)
};

/// Everything far-field that lights the scene besides its analytic lights.
struct Environment {
    SkyLight sky;
    std::vector<ReflectionCapture> captures;  //!< in ascending radius: Unreal's composite order
    bool empty() const { return !sky.enabled && captures.empty(); }
};

}  // namespace fp
