// reflection_environment (algorithms §8) against hand-worked values and the path-traced truth: a
// floor under a constant sky, specular occlusion, clear coat's energy, threads, pass-through.
#include "reference/ReflectionCaptureRenderer.h"
#include "foundation/RayScene.h"
#include "foundation/ShadingModel.h"
#include "shading/BRDF.h"
#include "shading/EnvBRDF.h"
#include "reference/TruthRenderer.h"
#include "passes/reflection_environment/ReflectionEnvironmentPass.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <tuple>

namespace fp {

namespace {

const Vec3f kSky{1.0f, 0.8f, 0.6f};

// A 200-unit floor (y = 0) of one material under a constant sky light, seen from above at an
// angle: every floor point sees nothing but sky above it.
Scene skyFloor(const Material& m) {
    Scene s;
    s.materials.push_back(m);
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 100.0));
    s.environment.sky.enabled = true;
    s.environment.sky.color = kSky;
    return s;
}

FrameCamera floorCamera(int size) {
    FrameCamera cam;
    cam.current = CameraView::lookAt({0, 30, -40}, {0, 0, 10}, {0, 1, 0}, 50.0, size, size, 1.0);
    cam.previous = cam.current;
    return cam;
}

struct Outputs {
    Image color, specular, diffuse;
    std::map<std::string, uint64_t> work;
};

Outputs runPass(test::MemorySource& src, std::map<std::string, std::string> inputs = {},
                nlohmann::json params = nlohmann::json::object()) {
    test::MemorySink sink;
    const Plan plan = test::planFor({test::node("reflection_environment", params, inputs)},
                                    {"reflection_environment.color", "reflection_environment.specular",
                                     "reflection_environment.diffuse"});
    const FrameReport report = executePlan(plan, src, sink);
    return {sink.layers.at("reflection_environment.color").image(),
            sink.layers.at("reflection_environment.specular").image(),
            sink.layers.at("reflection_environment.diffuse").image(), report.passes.back().work};
}

Material floorMaterial() {
    Material m;
    m.baseColor = {0.5f, 0.4f, 0.3f};
    m.specular = 0.5f;
    m.roughness = 0.4f;
    return m;
}

}  // namespace

TEST_CASE("reflection_environment: a floor under a constant sky, against the truth") {
    const Scene scene = skyFloor(floorMaterial());
    const FrameCamera cam = floorCamera(24);
    test::MemorySource src = test::captureToMemory(scene, cam);
    const Outputs out = runPass(src);

    TruthSettings ts;
    ts.samplesPerPixel = 256;
    const TruthResult truth = TruthRenderer(scene, cam, ts).render();
    const Image& full = truth.layers.at("Truth.DiffuseIndirectFull");
    const Image& spec = truth.layers.at("Truth.Specular");
    const Image& specErr = truth.layers.at("Truth.Specular.StdErr");
    const Image& base = src.buffers.at("BaseColor");
    int floorPixels = 0;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            if (std::isinf(src.buffers.at("SceneDepth").plane(0).at(x, y))) continue;
            ++floorPixels;
            for (int c = 0; c < 3; ++c) {
                // Every cosine ray of the open floor leaves to the sky: the truth's irradiance/π
                // is the sky's radiance with no noise, and SH3 holds a constant exactly (to the
                // float sum of the cube's solid angles).
                CHECK(full.plane(c).at(x, y) == doctest::Approx(kSky[c]).epsilon(1e-5));
                CHECK(out.diffuse.plane(c).at(x, y) ==
                      doctest::Approx(base.plane(c).at(x, y) * kSky[c]).epsilon(1e-4));
                // Specular: the split sum is exact for a constant sky, so the difference is the
                // table's own (≤ 0.055 of the sky's radiance, ReflectionMathTests) plus the
                // truth's noise (4σ).
                CHECK(std::abs(out.specular.plane(c).at(x, y) - spec.plane(c).at(x, y)) <=
                      0.055f * kSky[c] + 4.0f * specErr.plane(c).at(x, y));
                // The colour is SceneColor (black: no lights) + both.
                CHECK(out.color.plane(c).at(x, y) ==
                      doctest::Approx(out.diffuse.plane(c).at(x, y) + out.specular.plane(c).at(x, y)));
            }
        }
    CHECK(floorPixels > 200);
    CHECK(out.work.at("pixels") == uint64_t(floorPixels));
    CHECK(out.work.at("skippedPixels") == uint64_t(24 * 24 - floorPixels));

    SUBCASE("1 and 2 threads give the same bits") {
        Outputs one;
        {
            tbb::global_control only(tbb::global_control::max_allowed_parallelism, 1);
            one = runPass(src);
        }
        for (int c = 0; c < 3; ++c) CHECK(test::sameBits(one.color.plane(c), out.color.plane(c)));
    }
}

TEST_CASE("reflection_environment: AO dims the sky diffuse, specular occlusion the reflections") {
    // Lagarde's SO = saturate((NoV + AO)^(r²) − 1 + AO), by hand:
    // (0.5 + 0.5)^0.25 − 0.5 = 0.5; (0.2 + 0.7)^0.64 − 0.3 = e^(0.64·ln 0.9) − 0.3 = 0.634792.
    CHECK(ReflectionEnvironmentPass::specularOcclusion(0.5f, 0.5f, 0.5f) == doctest::Approx(0.5f));
    CHECK(ReflectionEnvironmentPass::specularOcclusion(0.2f, 0.7f, 0.8f) == doctest::Approx(0.634792f).epsilon(1e-5));
    CHECK(ReflectionEnvironmentPass::specularOcclusion(1.0f, 1.0f, 0.3f) == 1.0f);
    CHECK(ReflectionEnvironmentPass::specularOcclusion(0.0f, 0.0f, 0.3f) == 0.0f);

    const Scene scene = skyFloor(floorMaterial());
    const FrameCamera cam = floorCamera(16);
    test::MemorySource src = test::captureToMemory(scene, cam);
    src.buffers["Opacity"] = Image(16, 16, {"Y"}, 0.5f);  // a Y buffer the pass does not read itself
    const Outputs open = runPass(src);
    const Outputs occluded = runPass(src, {{"ao", "capture:Opacity"}});
    const Outputs noSO = runPass(src, {{"ao", "capture:Opacity"}}, {{"specularOcclusion", false}});
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            if (std::isinf(src.buffers.at("SceneDepth").plane(0).at(x, y))) continue;
            const Vec3d p = cam.current.translatedFromPixel(x, y, src.buffers.at("SceneDepth").plane(0).at(x, y));
            const float NoV = saturate(float(-p.y / length(p)));  // N = +y, V towards the eye
            const float so = ReflectionEnvironmentPass::specularOcclusion(NoV, 0.5f, 0.4f);
            // Sky visibility = min(GBufferAO = 1, AO = 0.5), occlusion tint black.
            CHECK(occluded.diffuse.plane(1).at(x, y) == doctest::Approx(0.5f * open.diffuse.plane(1).at(x, y)));
            CHECK(occluded.specular.plane(1).at(x, y) ==
                  doctest::Approx(so * open.specular.plane(1).at(x, y)).epsilon(1e-4));
            CHECK(noSO.specular.plane(1).at(x, y) == open.specular.plane(1).at(x, y));
        }
}

TEST_CASE("reflection_environment: clear coat under a white sky reflects at most what arrives") {
    // A metal (F0 = 1) under a clear coat in a white furnace: the base reflects EnvBRDF ≤ 1 of the
    // sky through the (1 − F_coat) the coat lets through, the coat F_coat: at most 1 in all.
    for (float coatRoughness : {0.05f, 0.5f}) {
        Material m;
        m.shadingModel = kClearCoat;
        m.baseColor = {1, 1, 1};
        m.metallic = 1.0f;
        m.roughness = 0.3f;
        m.clearCoat = 1.0f;
        m.clearCoatRoughness = coatRoughness;
        Scene s;
        s.materials.push_back(m);
        s.meshes.push_back(test::sphere({0, 0, 0}, 10.0, 48));
        s.environment.sky.enabled = true;
        const FrameCamera cam = [] {
            FrameCamera c;
            c.current = CameraView::lookAt({0, 0, -40}, {0, 0, 0}, {0, 1, 0}, 40.0, 32, 32, 1.0);
            c.previous = c.current;
            return c;
        }();
        test::MemorySource src = test::captureToMemory(s, cam);
        const Outputs out = runPass(src);
        float most = 0.0f, least = 2.0f;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                if (std::isinf(src.buffers.at("SceneDepth").plane(0).at(x, y))) continue;
                most = std::max(most, out.specular.plane(0).at(x, y));
                least = std::min(least, out.specular.plane(0).at(x, y));
            }
        CAPTURE(coatRoughness);
        CHECK(most <= 1.0f + 1e-5f);
        CHECK(least > 0.5f);  // a coated metal: most of the sky comes back
    }
}

TEST_CASE("reflection_environment: with no sky and no reflections the colour passes through") {
    Scene scene = skyFloor(floorMaterial());
    scene.environment.sky.enabled = false;
    const FrameCamera cam = floorCamera(8);
    test::MemorySource src = test::captureToMemory(scene, cam);
    src.buffers["SceneColor"] = Image(8, 8, {"R", "G", "B"}, 0.25f);
    const Outputs out = runPass(src);
    for (int c = 0; c < 3; ++c) {
        CHECK(test::sameBits(out.color.plane(c), src.buffers.at("SceneColor").plane(c)));
        CHECK(out.specular.plane(c).at(3, 5) == 0.0f);
    }
    CHECK(out.work.at("skippedPixels") == 64u);
    CHECK(out.work.count("pixels") == 0);
}

TEST_CASE("a reflection capture rendered inside a glowing box sees the glow everywhere") {
    // Six black faces glowing kGlow around the capture, no lights: every texel of every face is
    // the emission (float rounding of the 2×2 average).
    Scene s;
    s.materials.push_back(test::lambert(0.0f, test::kGlow));
    const Vec3d X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
    const double h = 50.0;
    for (const auto& [centre, u, v] : {std::tuple{X * h, Y, Z}, std::tuple{X * -h, Z, Y}, std::tuple{Y * h, Z, X},
                                       std::tuple{Y * -h, X, Z}, std::tuple{Z * h, X, Y}, std::tuple{Z * -h, Y, X}})
        s.meshes.push_back(test::quad(centre, u, v, h));
    const RayScene rays(s, {0, 0, 0});
    const Image faces = renderReflectionCapture(rays, {5, -3, 10}, 16);
    CHECK(faces.width() == 16);
    CHECK(faces.height() == 96);
    float least = 1.0f, most = 0.0f;
    for (int c = 0; c < 3; ++c)
        for (int y = 0; y < 96; ++y)
            for (int x = 0; x < 16; ++x) {
                least = std::min(least, faces.plane(c).at(x, y));
                most = std::max(most, faces.plane(c).at(x, y));
            }
    CHECK(least == doctest::Approx(test::kGlow).epsilon(1e-6));
    CHECK(most == doctest::Approx(test::kGlow).epsilon(1e-6));
}

}  // namespace fp
