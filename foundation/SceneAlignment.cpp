#include "foundation/SceneAlignment.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace fp {

SceneAlignment measureSceneAlignment(const RayScene& scene, const CameraView& camera,
                                     const Image& sceneDepth, int step, double scale) {
    SceneAlignment a;
    a.scale = scale;
    std::vector<double> ratios;
    // Ray origins relative to the scene's origin, as the BVH keeps its coordinates. The scene
    // scaled by s is hit where the unscaled one is by the ray from eye / s, at 1/s the distance.
    const Vec3d eye = camera.position * (1.0 / scale) - scene.origin();
    const Vec3f org{float(eye.x), float(eye.y), float(eye.z)};
    step = std::max(step, 1);
    for (int y = step / 2; y < sceneDepth.height(); y += step)
        for (int x = step / 2; x < sceneDepth.width(); x += step) {
            const float depth = sceneDepth.plane(0).at(x, y);
            if (!std::isfinite(depth) || !(depth > 0.0f)) continue;  // sky
            ++a.sampled;
            const Vec3d d = camera.rayDirection(x, y);
            const RayHit hit = scene.intersect(org, {float(d.x), float(d.y), float(d.z)}, 0.0f,
                                               std::numeric_limits<float>::infinity());
            if (!hit.hit) {
                ++a.missed;
                continue;
            }
            // The hit's view depth: its distance along the ray times the ray's cosine to the axis.
            const double traced = double(hit.t) * scale * dot(d, camera.forward);
            if (!(traced > 0.0)) continue;
            ratios.push_back(double(depth) / traced);
            if (std::fabs(traced - depth) <= SceneAlignment::kDepthTolerance * depth) ++a.agreeing;
        }
    if (!ratios.empty()) {
        std::vector<double> sorted = ratios;
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        a.medianDepthRatio = sorted[sorted.size() / 2];
        const auto near = std::count_if(ratios.begin(), ratios.end(), [&](double r) {
            return std::fabs(r - a.medianDepthRatio) <= 0.05 * a.medianDepthRatio;
        });
        a.ratioConsistency = double(near) / double(ratios.size());
    }
    return a;
}

SceneAlignment bestUnitScale(const RayScene& scene, const CameraView& camera,
                             const Image& sceneDepth, int step) {
    // Between metres, decimetres, centimetres, millimetres and kilometres (powers of ten), and
    // inches (2.54 cm, 25.4 mm, 39.37 per metre) and feet (30.48 cm, 304.8 mm, 3.281 per metre,
    // 12 inches); each is tried both ways.
    static const double kFactors[] = {10.0,  100.0, 1000.0, 1e4,   1e5,          1e6, 2.54,
                                      25.4,  1.0 / 0.0254, 30.48, 304.8, 1.0 / 0.3048, 12.0};
    SceneAlignment best = measureSceneAlignment(scene, camera, sceneDepth, step, 1.0);
    for (double f : kFactors)
        for (double s : {f, 1.0 / f}) {
            const SceneAlignment a = measureSceneAlignment(scene, camera, sceneDepth, step, s);
            if (a.agreeing > best.agreeing) best = a;
        }
    return best;
}

int alignmentStep(int width, int height, int rays) {
    const double area = double(width) * double(height);
    return std::max(1, int(std::floor(std::sqrt(area / std::max(rays, 1)))));
}

std::string describeMisalignment(const SceneAlignment& a, const SceneAlignment& units,
                                 double unitsToDeclare) {
    std::string s = fmt::format(
        "the scene does not line up with the capture: of {} surface pixels' camera rays, {} "
        "land within {:.0f} % of the capture's depth and {} hit nothing",
        a.sampled, a.agreeing, 100.0 * SceneAlignment::kDepthTolerance, a.missed);
    if (a.sampled > a.missed)
        s += fmt::format("; the capture's depth is {:.4g}× the traced one (median)",
                         a.medianDepthRatio);
    if (units.scale != 1.0 && units.agreeingFraction() >= 0.5) {
        // The scene lines up once scaled by one unit factor: it is in other units.
        s += fmt::format(
            ". Most likely units: scaled by {:.6g} the scene lines up ({} of {} rays agree); "
            "give the scene JSON \"sceneUnitsPerMeter\": {:.6g} (the capture's units are then "
            "converted to)",
            units.scale, units.agreeing, units.sampled, unitsToDeclare);
    } else if (a.missed > a.sampled / 2) {
        s += ". Most likely the camera looks elsewhere than the scene: a camera in other axes "
             "(a sidecar's \"axes\"), another frame's camera, or another scene";
    } else {
        s += ". Most likely another camera (position, field of view) or another scene than the "
             "one captured, or the scene moved (its \"offset\")";
    }
    return s;
}

}  // namespace fp
