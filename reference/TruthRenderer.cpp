#include "reference/TruthRenderer.h"

#include "foundation/RayScene.h"
#include "foundation/Random.h"
#include "foundation/Tiles.h"
#include "reference/PathTracer.h"

#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

namespace fp {

namespace {

constexpr uint32_t kSeedTruth = 0x54525554u;  // "TRUT"
constexpr float kInf = std::numeric_limits<float>::infinity();

// Running sums of one pixel's samples of a layer (up to 3 channels), in double so thousands of
// samples of HDR values keep their variance.
struct PixelStats {
    double sum[3] = {0, 0, 0}, sumSq[3] = {0, 0, 0};
    void add(const Vec3f& x) {
        for (int c = 0; c < 3; ++c) {
            sum[c] += x[c];
            sumSq[c] += double(x[c]) * x[c];
        }
    }
    void add(float x) { add(Vec3f{x, 0, 0}); }
    // Mean and the standard error of the mean (sample variance / n, Bessel-corrected).
    void store(Image& mean, Image& stdErr, int px, int py, int n) const {
        for (int c = 0; c < int(mean.channels().size()); ++c) {
            const double m = sum[c] / n;
            const double var = n > 1 ? std::max(0.0, (sumSq[c] - n * m * m) / (n - 1)) : 0.0;
            mean.plane(c).at(px, py) = float(m);
            stdErr.plane(c).at(px, py) = float(std::sqrt(var / n));
        }
    }
};

}  // namespace

std::vector<std::string> TruthRenderer::shadowLayerNames(const Scene& scene) {
    std::vector<std::string> names;
    for (const std::string& id : lightIdentifiers(scene.lights)) names.push_back("Truth.Shadow." + id);
    return names;
}

TruthResult TruthRenderer::render(const std::function<void(int, int)>& progress) const {
    const CameraView& cam = mCamera.current;
    const int W = cam.width, H = cam.height, N = mSettings.samplesPerPixel;
    const RayScene rs(mScene, cam.position);
    const PathTracer tracer(rs, mSettings.maxBounces);
    const DirectLighting& lighting = tracer.lighting();
    const float aoRadius = float(mSettings.aoRadius);
    const auto& lights = mScene.lights;
    auto isEmitter = [&](int mesh) {
        const Vec3f& e = mScene.materials[mScene.meshes[mesh].material].emission;
        return e.x > 0.0f || e.y > 0.0f || e.z > 0.0f;
    };

    TruthResult result;
    const std::vector<std::string> rgb = {"R", "G", "B"}, y = {"Y"};
    auto addLayer = [&](const std::string& name, const std::vector<std::string>& channels) {
        result.names.push_back(name);
        result.layers[name] = Image(W, H, channels);
        result.layers[name + ".StdErr"] = Image(W, H, channels);
    };
    addLayer("Truth.DiffuseIndirectOneBounce", rgb);
    addLayer("Truth.DiffuseIndirectFull", rgb);
    addLayer("Truth.AO", y);
    addLayer("Truth.AOAnyDistance", y);
    addLayer("Truth.Specular", rgb);
    addLayer("Truth.ReflectedEmitter", y);
    addLayer("Truth.Combined", rgb);
    const std::vector<std::string> shadowNames = shadowLayerNames(mScene);
    for (const auto& n : shadowNames) addLayer(n, y);
    // Plane lookups happen once, before the workers start (the map is not touched in parallel).
    struct Target { Image* mean; Image* stdErr; };
    auto target = [&](const std::string& name) {
        return Target{&result.layers.at(name), &result.layers.at(name + ".StdErr")};
    };
    const Target oneT = target("Truth.DiffuseIndirectOneBounce");
    const Target fullT = target("Truth.DiffuseIndirectFull");
    const Target aoT = target("Truth.AO"), specT = target("Truth.Specular");
    const Target aoAnyT = target("Truth.AOAnyDistance");
    const Target emitterT = target("Truth.ReflectedEmitter");
    const Target combinedT = target("Truth.Combined");
    std::vector<Target> shadowT;
    for (const auto& n : shadowNames) shadowT.push_back(target(n));

    std::atomic<uint64_t> rays{0};
    std::atomic<int> tilesDone{0};
    const int tilesTotal = ((W + kTileSize - 1) / kTileSize) * ((H + kTileSize - 1) / kTileSize);
    std::mutex progressMutex;

    forEachTile(W, H, [&](const Tile& t) {
        uint64_t tileRays = 0;
        std::vector<PixelStats> shadow(lights.size());
        std::vector<float> punctualVisibility(lights.size());
        for (int py = t.y0; py < t.y1; ++py)
            for (int px = t.x0; px < t.x1; ++px) {
                const Vec3f dir0(cam.rayDirection(px, py));
                ++tileRays;
                const RayHit primary = rs.intersect(Vec3f{}, dir0, 0.0f, kInf);
                if (!primary.hit) continue;  // sky: every layer stays 0
                const SurfacePoint s = surfaceAt(rs, primary, Vec3f{}, dir0);
                Rng rng(mSettings.frame, px, py, kSeedTruth);
                PixelStats one, full, ao, aoAny, spec, emitter, combined;
                std::fill(shadow.begin(), shadow.end(), PixelStats{});
                for (int i = 0; i < N; ++i) {
                    // Diffuse indirect and AO share one cosine-distributed ray.
                    const Gathered d = tracer.gather(s, ScatterLobe::Kind::Cosine, rng, tileRays);
                    one.add(d.oneBounce);
                    full.add(d.full);
                    // A ray into the surface's own back counts as occluded.
                    ao.add(d.sampled && (!d.hit || d.distance > aoRadius) ? 1.0f : 0.0f);
                    aoAny.add(d.sampled && !d.hit ? 1.0f : 0.0f);
                    const Gathered g = tracer.gather(s, ScatterLobe::Kind::Specular, rng, tileRays);
                    const Vec3f& specular = g.full;
                    spec.add(specular);
                    emitter.add(g.hit && isEmitter(g.mesh) ? 1.0f : 0.0f);
                    // The beauty: what the pixel emits, its direct light, and the two indirect
                    // lobes above (BSDF = diffuse/π + F·D·Vis, so diffuse reflection is
                    // DiffuseColor × the cosine-weighted mean).
                    combined.add(s.emission + lighting.shade(s, rng, tileRays) +
                                 s.brdf.diffuseColor * d.full + specular);

                    for (std::size_t l = 0; l < lights.size(); ++l) {
                        const float lu = rng.nextFloat(), lv = rng.nextFloat();
                        // A punctual light's visibility is one ray, the same for every sample.
                        // (The tracer's own DirectLighting takes one sample per light, so ask the
                        // light, not samplesFor.)
                        const bool punctual = !DirectLighting::hasExtent(lights[l]);
                        if (i > 0 && punctual) {
                            shadow[l].add(punctualVisibility[l]);
                            continue;
                        }
                        const LightSample ls = lighting.sample(lights[l], s, lu, lv);
                        float vis = 0.0f;
                        if (ls.reaches()) {
                            ++tileRays;
                            vis = lighting.visible(s, ls) ? 1.0f : 0.0f;
                        }
                        punctualVisibility[l] = vis;
                        shadow[l].add(vis);
                    }
                }
                one.store(*oneT.mean, *oneT.stdErr, px, py, N);
                full.store(*fullT.mean, *fullT.stdErr, px, py, N);
                ao.store(*aoT.mean, *aoT.stdErr, px, py, N);
                aoAny.store(*aoAnyT.mean, *aoAnyT.stdErr, px, py, N);
                spec.store(*specT.mean, *specT.stdErr, px, py, N);
                emitter.store(*emitterT.mean, *emitterT.stdErr, px, py, N);
                combined.store(*combinedT.mean, *combinedT.stdErr, px, py, N);
                for (std::size_t l = 0; l < lights.size(); ++l)
                    shadow[l].store(*shadowT[l].mean, *shadowT[l].stdErr, px, py, N);
            }
        rays += tileRays;
        const int done = ++tilesDone;
        if (progress) {
            std::lock_guard<std::mutex> lock(progressMutex);
            progress(done, tilesTotal);
        }
    });
    result.rays = rays;
    return result;
}

}  // namespace fp
