#include "reference/EmitterSampler.h"

#include "foundation/Sampling.h"

#include <algorithm>
#include <cmath>

namespace fp {

EmitterSampler::EmitterSampler(const RayScene& scene) : mScene(scene) {
    const Scene& sc = scene.scene();
    for (unsigned m = 0; m < sc.meshes.size(); ++m) {
        const Mesh& mesh = sc.meshes[m];
        const float lum = luminance(sc.emissionTowardsSurfaces(m));
        if (!(lum > 0.0f)) continue;
        for (unsigned t = 0; t + 2 < mesh.indices.size(); t += 3) {
            // Corners relative to the origin, subtracted in double (translated world).
            auto corner = [&](int k) {
                return Vec3f(mesh.positions[mesh.indices[t + k]] - scene.origin());
            };
            Triangle tri{m, t / 3, corner(0), corner(1), corner(2)};
            const double area = 0.5 * length(cross(Vec3d(tri.b - tri.a), Vec3d(tri.c - tri.a)));
            if (!(area > 0.0)) continue;
            mTotal += area * lum;
            mTriangles.push_back(tri);
            mCdf.push_back(mTotal);
        }
    }
    for (double& c : mCdf) c /= mTotal;
}

float EmitterSampler::pdfArea(unsigned mesh) const {
    const Scene& sc = mScene.scene();
    if (empty() || mesh >= sc.meshes.size()) return 0.0f;
    return float(luminance(sc.emissionTowardsSurfaces(mesh)) / mTotal);
}

EmitterPoint EmitterSampler::sample(float choose, float u, float v) const {
    const std::size_t i = std::min<std::size_t>(
        std::upper_bound(mCdf.begin(), mCdf.end(), double(choose)) - mCdf.begin(),
        mTriangles.size() - 1);
    const Triangle& t = mTriangles[i];
    // Uniform point on the triangle (square-root warp of the barycentrics).
    const float su = std::sqrt(u);
    const float b0 = 1.0f - su, b1 = v * su;
    EmitterPoint p;
    p.position = t.a * b0 + t.b * b1 + t.c * (1.0f - b0 - b1);
    p.normal = normalize(cross(t.b - t.a, t.c - t.a));
    p.mesh = t.mesh;
    p.triangle = t.index;
    p.emission = mScene.scene().emissionTowardsSurfaces(t.mesh);
    p.pdfArea = pdfArea(t.mesh);
    return p;
}

}  // namespace fp
