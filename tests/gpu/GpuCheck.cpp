// framepass_gpu_check: the CUDA backend checked where a GPU is. Without arguments it runs the
// doctest cases below (the GPU's outputs against the CPU's on the Cornell, glossy and hard
// captures; on a machine without a GPU each case says why it skipped and the check exits 77); with
// --bench it times the demo chain with SSR and the reflection environment on the GPU and the CPU,
// and the workbench's re-run. It links only the core, the passes, OpenEXR and the scene loaders,
// so it runs on a GPU machine without OpenImageIO's dependency tree (docs/gpu.md).
#define DOCTEST_CONFIG_IMPLEMENT
#include "io/ConfigLoader.h"
#include "io/scene/SceneLoader.h"
#include "reference/ReflectionCaptureRenderer.h"
#include "foundation/Cuda.h"
#include "foundation/RayScene.h"
#include "framework/Executor.h"
#include "framework/PassRegistry.h"
#include "framework/Planner.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {
using namespace fp;

// The repository (for the example scenes): where it was built, or $FRAMEPASS_SOURCE_DIR on a
// machine the binary was carried to.
std::string sourceDir() {
    const char* env = std::getenv("FRAMEPASS_SOURCE_DIR");
    return env && *env ? env : FP_SOURCE_DIR;
}

// A scene: the examples' name (cornell, glossy, hard, dense) or a scene JSON's path.
std::string scenePath(const std::string& nameOrPath) {
    if (nameOrPath.find('/') == std::string::npos && nameOrPath.find(".json") == std::string::npos)
        return sourceDir() + "/examples/" + nameOrPath + "/scene.json";
    return nameOrPath;
}

// A scene's capture rendered in memory, as `framepass capture` renders it (16 light samples),
// with the reflection captures the scene names rendered from it as a session renders them.
struct Capture {
    io::SceneFile scene;
    test::MemorySource source;
};

std::unique_ptr<Capture> captureScene(const std::string& scene, Extent extent, int frame) {
    auto c = std::make_unique<Capture>();
    c->scene = io::loadScene(scenePath(scene));
    const Extent size = extent.width > 0 ? extent : c->scene.resolution;
    const FrameCamera camera = c->scene.cameraForFrame(frame, size);
    CaptureSettings settings;
    settings.frame = frame;
    c->source.buffers = GBufferRenderer(c->scene.scene, camera, settings).render().buffers;
    renderMissingReflectionCaptures(c->scene.scene);
    c->source.info.number = frame;
    c->source.info.extent = size;
    c->source.info.camera = camera;
    c->source.info.hasCamera = true;
    c->source.sceneData = &c->scene.scene;
    return c;
}

// Which chain a check or bench runs, and how.
struct ChainOptions {
    std::string device = "cpu";
    std::vector<std::string> dumps{};  //!< outputs asked for besides the config's ("all": every one)
    bool errors = false;       //!< two error_measure steps, so every pass with a kernel runs
    bool reflections = false;  //!< SSR (Epic, temporal) and the reflection environment
    int quality = 4;
    bool halfRes = false;
    bool workbench = false;    //!< planned as `framepass serve` plans: every pass, only the dumps
    /// The scene's lights: per light, as the engine preset lights it, a ray-traced shadow, its
    /// denoiser and the deferred lighting, the chain then starting from the capture's emissive.
    std::vector<std::string> lights{};
    /// rt_shadows' traversal where set ("bvh": the GPU's own code on the CPU, for same bits).
    std::string traversal{};
    bool film = false;  //!< the display through Unreal's filmic tonemapper, not the OCIO view
};

std::vector<std::string> lightsOf(const Scene& scene) {
    std::vector<std::string> names;
    for (const Light& l : scene.lights) names.push_back(l.name);
    return names;
}

// The engine preset's chain: its screen-space passes, then where asked each light's shadow rays,
// their denoiser and the deferred lighting, and SSR and the reflection environment before the
// display (without either it is the demo chain of `make demo`), with framepass's two hybrids
// beside them for their dumps. The errors are
// the GI against the capture's colour, with a standard error, and the AO against the GBuffer's
// AO, with the screen-space oracle beside them. SSR runs at Epic (12 glossy rays, the single
// mirror ray below roughness 0.1) with its temporal smoothing, and traces every surface up to
// roughness 1.
Plan chainPlan(const ChainOptions& o) {
    nlohmann::json passes = nlohmann::json::parse(R"([
      { "name": "hzb", "type": "hzb" },
      { "name": "prev_color_reduction", "type": "prev_color_reduction",
        "inputs": { "furthestHzb": "hzb.furthest" } },
      { "name": "ssgi", "type": "ssgi",
        "inputs": { "furthestHzb": "hzb.furthest", "reducedColor": "prev_color_reduction.color" } },
      { "name": "ssgi_denoise", "type": "ssgi_denoise",
        "inputs": { "diffuse": "ssgi.diffuse", "ao": "ssgi.ao" } },
      { "name": "diffuse_indirect_composite", "type": "diffuse_indirect_composite",
        "inputs": { "diffuse": "ssgi_denoise.diffuse", "ao": "ssgi_denoise.ao" } },
      { "name": "camera_velocity", "type": "camera_velocity" }
    ])");
    passes[2]["params"] = {{"quality", o.quality}, {"halfRes", o.halfRes}};
    passes[3]["params"] = {{"halfRes", o.halfRes}};
    std::string lit = "diffuse_indirect_composite.color";
    if (!o.lights.empty()) {
        passes.push_back(nlohmann::json::parse(R"({ "forEachLight": {
          "colorIn": "diffuse_indirect_composite.color",
          "passes": [
            { "name": "rt_shadows_{light}", "type": "rt_shadows", "params": { "light": "{lightName}" } },
            { "name": "shadow_denoise_{light}", "type": "shadow_denoise", "params": { "light": "{lightName}" },
              "inputs": { "shadow": "rt_shadows_{light}.shadow", "transmission": "rt_shadows_{light}.transmission",
                          "hitDistance": "rt_shadows_{light}.hitDistance" } },
            { "name": "deferred_lighting_{light}", "type": "deferred_lighting", "params": { "light": "{lightName}" },
              "inputs": { "color": "{colorIn}", "attenuation": "shadow_denoise_{light}.lightAttenuation" } }
          ],
          "colorOut": "deferred_lighting_{light}.color",
          "rewire": { "diffuse_indirect_composite.sceneColor": "capture:Emissive" } } })"));
        if (!o.traversal.empty())
            passes.back()["forEachLight"]["passes"][0]["params"]["traversal"] = o.traversal;
        // The lit colour goes on to what follows the composite.
        passes.back()["forEachLight"]["rewire"][o.reflections ? "reflection_environment.color" : "display.color"] =
            "{colorOut}";
    }
    if (o.reflections) {
        passes.push_back({{"name", "ssr"},
                          {"type", "ssr"},
                          {"params", {{"quality", 4}, {"postProcessQuality", 100},
                                      {"maxRoughness", 1.0}, {"temporal", true}}},
                          {"inputs", {{"furthestHzb", "hzb.furthest"}}}});
        // framepass's two hybrids beside them, run for their dumps: SSGI's rays with the scene
        // behind them (2 bounces, on-screen hits continued), SSR's with the scene behind them.
        passes.push_back({{"name", "hybrid"},
                          {"type", "hybrid"},
                          {"params", {{"quality", 1}, {"maxBounces", 2}, {"continueOnScreen", true}}},
                          {"inputs", {{"furthestHzb", "hzb.furthest"},
                                      {"reducedColor", "prev_color_reduction.color"}}}});
        if (!o.traversal.empty()) passes.back()["params"]["traversal"] = o.traversal;
        passes.push_back({{"name", "hybrid_reflections"},
                          {"type", "hybrid_reflections"},
                          {"params", {{"quality", 4}, {"postProcessQuality", 100},
                                      {"maxRoughness", 1.0}, {"temporal", true}}},
                          {"inputs", {{"furthestHzb", "hzb.furthest"}}}});
        if (!o.traversal.empty()) passes.back()["params"]["traversal"] = o.traversal;
        passes.push_back({{"name", "reflection_environment"},
                          {"type", "reflection_environment"},
                          {"inputs", {{"color", lit}, {"reflection", "ssr.reflection"},
                                      {"ao", "ssgi_denoise.ao"}}}});
        lit = "reflection_environment.color";
    }
    passes.push_back({{"name", "display"}, {"type", "display"}, {"inputs", {{"color", lit}}}});
    if (o.film) passes.back()["params"] = {{"tonemapper", "ue4.27-film"}};
    nlohmann::json config = {{"version", 1}, {"capture", "memory.exr"}};
    config["outputs"] = {{"final.####.exr", "display.image"}};
    if (o.errors) {
        passes.push_back(nlohmann::json::parse(R"(
          { "name": "gi_vs_color", "type": "error_measure",
            "inputs": { "source": "ssgi_denoise.diffuse", "reference": "capture:SceneColor",
                        "referenceStdErr": "capture:BaseColor" } })"));
        passes.push_back(nlohmann::json::parse(R"(
          { "name": "ao_vs_gbuffer", "type": "error_measure",
            "params": { "skyDistance": 1e6, "excludeAbove": 0.5 },
            "inputs": { "source": "ssgi_denoise.ao", "reference": "capture:GBufferAO",
                        "exclude": "capture:Roughness" } })"));
        // The error breakdown's oracle, culled unless a dump asks for it.
        passes.push_back({{"name", "oracle"}, {"type", "screen_space_oracle"}, {"params", {{"rays", 16}}}});
        config["outputs"] = {{"final.####.exr", {"display.image", "gi_vs_color.heat",
                                                 "gi_vs_color.absError", "ao_vs_gbuffer.heat"}}};
    }
    config["passes"] = passes;
    io::RunConfig rc = io::parseRunConfig(config, "gpu check", sourceDir());
    PlanInputs inputs;
    inputs.overrides.device = o.device;
    inputs.overrides.dumps = o.dumps;
    inputs.overrides.runEveryPass = o.workbench;
    inputs.overrides.dumpsOnly = o.workbench;
    inputs.lightNames = o.lights;
    return makePlan(rc.graph, builtinPasses(), inputs);
}

struct Difference {
    std::string layer;
    double maxAbs = 0, maxRel = 0;  //!< rel: |a − b| / max(|a|, |b|, 1e-3)
    int64_t differing = 0, pixels = 0;
    std::string first;  //!< the first differing value, for a look
};

// Every layer of a run compared, and its error_measure figures.
struct Comparison {
    std::vector<Difference> layers;
    double metricMaxRel = 0;  //!< largest relative difference of an error_measure figure
    std::string metricWorst;
    int metrics = 0;
    /// The GPU's shadow rays against Embree's (the CPU's default traversal): pixels whose
    /// visibility differs, of all shadow pixels, and the largest differences where it agrees.
    int64_t embreeShadowDiffering = 0, embreeShadowPixels = 0;
    double embreeTransmissionMaxAbs = 0, embreeHitDistanceMaxRel = 0;
    bool film = false;  //!< the display ran Unreal's filmic tonemapper
};

// rt_shadows' outputs of the GPU against a CPU run through Embree: the two triangle tests round
// differently, so a ray within a few float steps of an edge may decide the other way.
void compareWithEmbree(const test::MemorySink& embree, const test::MemorySink& gpu, Comparison& out) {
    for (const auto& [name, a] : embree.layers) {
        const auto dot = name.find('.');
        if (name.rfind("rt_shadows_", 0) != 0 || name.substr(dot) != ".shadow") continue;
        const std::string pass = name.substr(0, dot);
        const Plane& se = a.image().plane(0);
        const Plane& sg = gpu.layers.at(name).image().plane(0);
        const Plane& te = embree.layers.at(pass + ".transmission").image().plane(0);
        const Plane& tg = gpu.layers.at(pass + ".transmission").image().plane(0);
        const Plane& he = embree.layers.at(pass + ".hitDistance").image().plane(0);
        const Plane& hg = gpu.layers.at(pass + ".hitDistance").image().plane(0);
        for (int y = 0; y < se.height(); ++y)
            for (int x = 0; x < se.width(); ++x) {
                ++out.embreeShadowPixels;
                if (se.at(x, y) != sg.at(x, y) || (he.at(x, y) < 0.0f) != (hg.at(x, y) < 0.0f)) {
                    ++out.embreeShadowDiffering;
                    continue;
                }
                out.embreeTransmissionMaxAbs = std::max(
                    out.embreeTransmissionMaxAbs, double(std::fabs(te.at(x, y) - tg.at(x, y))));
                if (he.at(x, y) > 0.0f)
                    out.embreeHitDistanceMaxRel = std::max(
                        out.embreeHitDistanceMaxRel,
                        std::fabs(double(he.at(x, y)) - hg.at(x, y)) / double(he.at(x, y)));
            }
    }
}

// Per layer and mip (mips after the first are reported as "layer@mip"), with the first
// differing value of each for a look.
std::vector<Difference> compare(const test::MemorySink& cpu, const test::MemorySink& gpu) {
    std::vector<Difference> out;
    for (const auto& [layer, a] : cpu.layers) {
        const std::string& name = layer;  // (clang 14 cannot capture a structured binding)
        auto it = gpu.layers.find(name);
        REQUIRE_MESSAGE(it != gpu.layers.end(), "the GPU run did not write " << name);
        const Texture& b = it->second;
        REQUIRE(a.mipCount() == b.mipCount());
        for (int m = 0; m < a.mipCount(); ++m) {
            Difference d;
            d.layer = m == 0 ? name : fmt::format("{}@{}", name, m);
            for (int c = 0; c < a.mip(m).channelCount(); ++c) {
                const Plane& pa = a.mip(m).plane(c);
                const Plane& pb = b.mip(m).plane(c);
                REQUIRE(pa.width() == pb.width());
                REQUIRE(pa.height() == pb.height());
                for (int y = 0; y < pa.height(); ++y)
                    for (int x = 0; x < pa.width(); ++x) {
                        const float va = pa.at(x, y), vb = pb.at(x, y);
                        ++d.pixels;
                        if (std::memcmp(&va, &vb, sizeof va) == 0)
                            continue;
                        if (d.differing++ == 0)
                            d.first = fmt::format("({},{}) ch {}: cpu {} gpu {}", x, y, c, va, vb);
                        const double diff = std::fabs(double(va) - double(vb));
                        d.maxAbs = std::max(d.maxAbs, diff);
                        d.maxRel = std::max(
                            d.maxRel, diff / std::max({std::fabs(double(va)), std::fabs(double(vb)),
                                                       1e-3}));
                    }
            }
            out.push_back(d);
        }
    }
    return out;
}

bool skipWithoutGpu() {
    const std::string why = cuda::unavailableReason();
    if (why.empty())
        return false;
    MESSAGE("skipped: " << why);
    return true;
}

void printDifferences(const std::string& what, const Comparison& c) {
    std::cout << fmt::format("GPU against CPU, {} ({}):\n", what, cuda::deviceName());
    std::cout << fmt::format("  {:<40} {:>12} {:>12} {:>10}\n", "layer", "max |Δ|", "max rel",
                             "differing");
    for (const auto& d : c.layers)
        std::cout << fmt::format("  {:<40} {:>12.3g} {:>12.3g} {:>9.4f}%  {}\n", d.layer, d.maxAbs,
                                 d.maxRel, 100.0 * double(d.differing) / double(d.pixels),
                                 d.first);
    std::cout << fmt::format("  error_measure figures: {} compared, largest relative difference "
                             "{:.3g} {}\n",
                             c.metrics, c.metricMaxRel, c.metricWorst);
    std::cout << fmt::format("  shadow rays against Embree's: visibility differs at {} of {} "
                             "pixels; where it agrees, transmission within {:.3g}, closest "
                             "occluder within {:.3g} relative\n",
                             c.embreeShadowDiffering, c.embreeShadowPixels,
                             c.embreeTransmissionMaxAbs, c.embreeHitDistanceMaxRel);
}

// A plan for a device ("cpu" or "cuda") and rt_shadows' traversal ("" the pass's default, Embree's
// on the CPU; "bvh" the GPU's own code).
using PlanFor = std::function<Plan(const std::string& device, const std::string& traversal)>;

// Frames 1–3 of a scene on both devices, the temporal passes' history carried from frame to frame
// (on the GPU it stays in device memory). Every layer of every frame, and every metric.
Comparison runPlans(const std::string& scene, Extent extent, const PlanFor& planFor,
                    bool film = false) {
    Comparison out;
    out.film = film;
    const Plan embreePlan = planFor("cpu", "");
    const Plan cpuPlan = planFor("cpu", "bvh");  // the GPU's own traversal on the CPU: same bits
    const Plan gpuPlan = planFor("cuda", "bvh");
    HistoryStore cpuHistory, gpuHistory, embreeHistory;
    for (int frame = 1; frame <= 3; ++frame) {
        auto cap = captureScene(scene, extent, frame);
        cap->source.info.firstInSequence = frame == 1;
        test::MemorySink cpu, gpu, embree;
        const FrameReport cr = executePlan(cpuPlan, cap->source, cpu, {}, &cpuHistory);
        const FrameReport gr = executePlan(gpuPlan, cap->source, gpu, {}, &gpuHistory);
        executePlan(embreePlan, cap->source, embree, {}, &embreeHistory);
        compareWithEmbree(embree, gpu, out);
        for (Difference& d : compare(cpu, gpu)) {
            d.layer = fmt::format("f{} {}", frame, d.layer);
            out.layers.push_back(std::move(d));
        }
        REQUIRE(cr.passes.size() == gr.passes.size());
        for (std::size_t p = 0; p < cr.passes.size(); ++p)
            for (const auto& [name, value] : cr.passes[p].metrics) {
                const double g = gr.passes[p].metrics.at(name);
                const double rel = std::fabs(g - value) / std::max(std::fabs(value), 1e-30);
                ++out.metrics;
                if (rel > out.metricMaxRel || (value != g && out.metricWorst.empty())) {
                    out.metricMaxRel = rel;
                    out.metricWorst = fmt::format("f{} {}.{}: cpu {:.17g} gpu {:.17g}", frame,
                                                  cr.passes[p].name, name, value, g);
                }
            }
    }
    return out;
}

// The check's chain (chainPlan) on both devices.
Comparison runBoth(const std::string& scene, Extent extent, int quality = 4, bool halfRes = false,
                   bool film = false) {
    const ChainOptions o{.dumps = {"all"}, .errors = true, .reflections = true,
                         .quality = quality, .halfRes = halfRes,
                         .lights = lightsOf(io::loadScene(scenePath(scene)).scene), .film = film};
    return runPlans(
        scene, extent,
        [&](const std::string& device, const std::string& traversal) {
            ChainOptions d = o;
            d.device = device;
            d.traversal = traversal;
            return chainPlan(d);
        },
        film);
}

// The ray-traced preset (configs/ue4.27-raytracing.json) as a user runs it, every output dumped:
// the passes without a CUDA kernel run on the CPU in both plans, so each kernel (the ray tracers'
// against the CPU's traversal "bvh", the signal denoisers') is compared on the same inputs.
Plan raytracedPlan(const std::string& device, const std::string& traversal,
                   const std::vector<std::string>& lights, const nlohmann::json& giParams = {}) {
    std::ifstream file(sourceDir() + "/configs/ue4.27-raytracing.json");
    REQUIRE_MESSAGE(file, "cannot read configs/ue4.27-raytracing.json under " << sourceDir());
    nlohmann::json config = nlohmann::json::parse(file, nullptr, true, /*ignore_comments=*/true);
    config["capture"] = "memory.exr";
    // The ray tracers with a GPU kernel take the traversal asked for (on the GPU they always
    // traverse framepass's BVH).
    for (nlohmann::json& pass : config["passes"]) {
        if (traversal.empty()) continue;
        if (pass.contains("forEachLight"))
            pass["forEachLight"]["passes"][0]["params"]["traversal"] = traversal;
        else if (pass.value("type", "").rfind("rt_", 0) == 0)  // the ray tracers
            pass["params"]["traversal"] = traversal;
    }
    for (nlohmann::json& pass : config["passes"])
        if (pass.value("type", "") == "rt_global_illumination")
            for (const auto& [key, value] : giParams.items()) pass["params"][key] = value;
    io::RunConfig rc = io::parseRunConfig(config, "gpu check", sourceDir());
    PlanInputs inputs;
    inputs.overrides.device = device;
    inputs.overrides.dumps = {"all"};
    inputs.lightNames = lights;
    return makePlan(rc.graph, builtinPasses(), inputs);
}

Comparison runRaytraced(const std::string& scene, Extent extent,
                        const nlohmann::json& giParams = {}) {
    const std::vector<std::string> lights = lightsOf(io::loadScene(scenePath(scene)).scene);
    return runPlans(scene, extent, [&](const std::string& device, const std::string& traversal) {
        return raytracedPlan(device, traversal, lights, giParams);
    });
}

// The tolerance of each output (docs/gpu.md). The kernels run the CPU's own FP_HD code without
// FMA contraction, with IEEE division and square root, and the CPU traces rt_shadows' rays through
// the GPU's own BVH code (traversal "bvh"), so outputs are expected bit for bit except:
// - ssgi.hitDistance, a debug output: its distance goes through a float→double→float path whose
//   last bit was seen to differ (largest relative difference 1.4e-4 on the hard capture, whose hits
//   are 10⁷ units from the origin); 1e-3 leaves room for other scenes.
// - display.image: OCIO's processor baked per half-float and interpolated (DisplayKernel.h);
//   DisplayTests bounds it at 4e-7 against OCIO's CPU processor on [0, 1]. Through Unreal's
//   filmic tonemapper both run the same code, but CUDA's log10f, expf, atan2f and powf are
//   within 2–4 float steps of glibc's; the curve's slope in log10 is below 1 and the sRGB
//   encoding's below 13 only where values are under 0.0031: 2e-6 bounds it with room.
// - error_measure heat maps: CUDA's powf (sRGB decoding of the colour map) is within 2 float steps
//   of glibc's; 1e-6 relative.
// - error_measure figures (the run report): the same terms summed in another order in double;
//   N ≤ 10⁷ terms give a relative difference below N·2⁻⁵³ ≈ 1e-9 (sums of non-negative terms).
void checkAgreement(const Comparison& c, int minMetrics = 3 * 2 * 7) {
    REQUIRE(c.layers.size() >= 3 * 9);  // every pass of the chain wrote something, every frame
    for (const auto& d : c.layers) {
        INFO(d.layer << ": " << d.first);
        const std::string layer = d.layer.substr(d.layer.find(' ') + 1);
        if (layer.rfind("ssgi.hitDistance", 0) == 0)
            CHECK(d.maxRel <= 1e-3);
        else if (layer.rfind("display.image", 0) == 0)
            CHECK(d.maxAbs <= (c.film ? 2e-6 : 4e-7));
        else if (layer.find(".heat") != std::string::npos)
            CHECK(d.maxRel <= 1e-6);
        else
            CHECK(d.differing == 0);
    }
    INFO(c.metricWorst);
    CHECK(c.metrics >= minMetrics);
    CHECK(c.metricMaxRel <= 1e-9);
    // Against Embree (tests/foundation/BvhTests.cpp and the rt_shadows tests bound the same on
    // the CPU): a pixel differs only where one of its rays passes within a few float steps of a
    // triangle's edge, at most one pixel in a thousand. A distance is within a few float steps
    // (6e-8 relative) of the coordinates it comes from, which in these rooms are up to 100× the
    // shortest occluder distances (contact shadows): 1e-4 relative (1.5e-5 was seen on Cornell).
    CHECK(c.embreeShadowPixels > 0);
    CHECK(c.embreeShadowDiffering * 1000 <= c.embreeShadowPixels);
    CHECK(c.embreeTransmissionMaxAbs <= 1e-4);
    CHECK(c.embreeHitDistanceMaxRel <= 1e-4);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// The chain a config file names (`--bench --config F`), its light templates expanded over the
// scene's lights; its capture is not read: the bench's own capture of the scene stands for it.
Plan configPlan(const std::string& path, const std::string& device, const Scene& scene) {
    const io::RunConfig rc = io::loadRunConfig(path);
    PlanInputs inputs;
    inputs.overrides.device = device;
    if (!rc.graph.lightTemplates.empty())
        inputs.lightNames = lightsOf(scene);
    return makePlan(rc.graph, builtinPasses(), inputs);
}

// --bench: medians of `runs` frames of the demo chain with reflections (or of a config's chain)
// on the GPU and on the CPU, per pass.
int bench(const std::string& scene, Extent extent, int runs, const std::string& jsonPath,
          const std::string& config) {
    if (const std::string why = cuda::unavailableReason(); !why.empty()) {
        std::cerr << "framepass_gpu_check --bench: " << why << "\n";
        return 2;
    }
    // As a run on the GPU reads its capture: into page-locked memory (the executor installs it
    // before its first GPU pass; here the capture is made before that).
    cuda::usePinnedHostMemory();
    auto cap = captureScene(scene, extent, 1);
    const Extent size = cap->source.info.extent;
    nlohmann::json result = {{"scene", scene},
                             {"width", size.width},
                             {"height", size.height},
                             {"gpu", cuda::deviceName()},
                             {"runs", runs}};
    // The CPU's run records its rays (the same rays as the GPU's: one ray generation; for a
    // config's closest hits, the same within the two traversals' rounding) for the bare
    // traversal kernel below: the demo chain's shadow rays, or every ray of a config's passes.
    RayScene::RayLog rayLog;
    uint64_t passRays = 0;
    double passRaySeconds = 0;
    for (const std::string device : {"cuda", "cpu"}) {
        const Plan plan =
            config.empty() ? chainPlan({.device = device, .reflections = true,
                                        .lights = lightsOf(cap->scene.scene)})
                           : configPlan(config, device, cap->scene.scene);
        std::map<std::string, std::vector<double>> wall, gpu;
        std::map<std::string, uint64_t> rays;
        std::vector<double> frames, transfers, uploads, downloads;
        double upBytes = 0, downBytes = 0;
        for (int r = 0; r < runs + 1; ++r) {  // the first run warms up (allocations, module load)
            test::MemorySink sink;
            const bool logRays = device == "cpu" && r == 0;
            if (logRays)
                cap->source.scene().setRayLog(&rayLog);
            const FrameReport rep = executePlan(plan, cap->source, sink);
            if (logRays)
                cap->source.scene().setRayLog(nullptr);
            if (r == 0)
                continue;
            frames.push_back(rep.seconds);
            upBytes = double(rep.uploadBytes);
            downBytes = double(rep.downloadBytes);
            transfers.push_back(rep.transferSeconds());
            uploads.push_back(rep.uploadSeconds);
            downloads.push_back(rep.downloadSeconds);
            for (const auto& p : rep.passes) {
                if ((p.type == "rt_shadows" || !config.empty()) && p.work.count("rays"))
                    rays[p.name] = p.work.at("rays");
                wall[p.name].push_back(p.seconds);
                if (p.gpuSeconds)
                    gpu[p.name].push_back(*p.gpuSeconds);
            }
        }
        nlohmann::json dj = {{"frameSeconds", median(frames)},
                             {"transferSeconds", median(transfers)},
                             {"uploadSeconds", median(uploads)},
                             {"downloadSeconds", median(downloads)}};
        double kernels = 0;
        std::cout << fmt::format("{} at {}×{} ({}), medians of {} runs:\n", device, size.width,
                                 size.height, device == "cuda" ? cuda::deviceName() : "CPU",
                                 runs);
        for (const auto& step : plan.steps) {
            const double w = median(wall[step.name]);
            const bool onGpu = gpu.count(step.name) > 0;
            const double g = onGpu ? median(gpu[step.name]) : 0.0;
            kernels += onGpu ? g : w;
            dj["passes"][step.name] = {{"wallSeconds", w}, {"device", onGpu ? "cuda" : "cpu"}};
            if (onGpu)
                dj["passes"][step.name]["gpuSeconds"] = g;
            if (onGpu && rays.count(step.name)) {
                passRays += rays[step.name];
                passRaySeconds += g;
            }
            std::cout << fmt::format("  {:<28} {:>4} {:>10.3f} ms wall{}\n", step.name,
                                     onGpu ? "gpu" : "cpu", w * 1e3,
                                     onGpu ? fmt::format(" {:>10.3f} ms GPU (events)", g * 1e3)
                                           : "");
        }
        dj["passSeconds"] = kernels;
        std::cout << fmt::format("  passes {:.3f} ms (GPU passes by events); frame {:.3f} ms wall, "
                                 "of it host↔GPU copies {:.3f} ms: up {:.3f} ms ({:.1f} MB), "
                                 "down {:.3f} ms ({:.1f} MB)\n",
                                 kernels * 1e3, median(frames) * 1e3, median(transfers) * 1e3,
                                 median(uploads) * 1e3, upBytes / 1e6, median(downloads) * 1e3,
                                 downBytes / 1e6);
        result[device] = dj;
    }
    if (!config.empty() && passRays > 0) {
        // A config's ray-tracing passes against the bare kernel tracing their rays alone: the
        // closest-hit rays each a closest-hit query, the shadow rays as the passes asked them.
        uint64_t hits = 0, blocked = 0;
        const BvhView bvh = cap->source.scene().deviceBvh();
        const double closest = cuda::timeBareTraversal(bvh, rayLog.closestRays, true, runs, hits);
        const double shadow =
            cuda::timeBareTraversal(bvh, rayLog.rays, rayLog.closestHits, runs, blocked);
        std::cout << fmt::format(
            "rays on the GPU: the passes that trace take {:.3f} ms for {} rays ({:.3f} G rays/s); "
            "bare traversal of the CPU run's rays: {} closest-hit rays {:.3f} ms ({:.3f} G "
            "rays/s, {} hit), {} shadow rays {:.3f} ms ({} blocked); together {:.3f} ms: the "
            "passes keep {:.0f}%\n",
            passRaySeconds * 1e3, passRays, double(passRays) / passRaySeconds / 1e9,
            rayLog.closestRays.size(), closest * 1e3,
            closest > 0 ? double(rayLog.closestRays.size()) / closest / 1e9 : 0.0, hits,
            rayLog.rays.size(), shadow * 1e3, blocked, (closest + shadow) * 1e3,
            100.0 * (closest + shadow) / passRaySeconds);
        result["cuda"]["bareRays"] = {{"passSeconds", passRaySeconds},
                                      {"passRays", passRays},
                                      {"closestRays", rayLog.closestRays.size()},
                                      {"closestSeconds", closest},
                                      {"shadowRays", rayLog.rays.size()},
                                      {"shadowSeconds", shadow}};
    }
    if (config.empty() && passRays > 0 && !rayLog.rays.empty()) {
        // rays/s of the pass (its rays over its kernel time: set-up, ray generation, traversal,
        // transmission and resolve) against the bare kernel tracing the same rays alone.
        uint64_t blocked = 0;
        const double bare = cuda::timeBareTraversal(cap->source.scene().deviceBvh(), rayLog.rays,
                                                    rayLog.closestHits, runs, blocked);
        const double passRate = double(passRays) / passRaySeconds;
        const double bareRate = double(rayLog.rays.size()) / bare;
        std::cout << fmt::format(
            "shadow rays on the GPU: rt_shadows {:.3f} G rays/s ({} rays in {:.3f} ms); bare "
            "traversal of the same {} rays{} {:.3f} G rays/s ({:.3f} ms, {} blocked): the pass "
            "keeps {:.0f}%\n",
            passRate / 1e9, passRays, passRaySeconds * 1e3, rayLog.rays.size(),
            rayLog.closestHits ? " (closest-hit queries, as the pass asks)" : "", bareRate / 1e9,
            bare * 1e3, blocked, 100.0 * passRate / bareRate);
        result["cuda"]["shadowRays"] = {{"passRaysPerSecond", passRate},
                                        {"bareRaysPerSecond", bareRate},
                                        {"rays", passRays},
                                        {"bareRays", rayLog.rays.size()},
                                        {"closestHits", rayLog.closestHits}};
    }
    // The workbench's re-run (framepass serve, docs/results/serve.md), of the demo chain only,
    // so not under --config: r.SSGI.Quality moved between 4 and 2 with the session's step cache,
    // planned as the workbench plans it (every pass runs, only the shown output comes back to the
    // host: the page's default A, the measured GI). Also with every pass output brought back, as
    // the workbench did before.
    if (config.empty())
        for (const auto& [device, everyOutput] : std::vector<std::pair<std::string, bool>>{
                 {"cuda", false}, {"cuda", true}, {"cpu", false}}) {
            ChainOptions o{.device = device, .errors = true, .workbench = true};
            o.dumps = {everyOutput ? "all" : "ssgi_denoise.diffuse"};
            o.quality = 4;
            const Plan four = chainPlan(o);
            o.quality = 2;
            const Plan plans[2] = {four, chainPlan(o)};
            StepCache cache;
            cache.sourceId = "bench capture";
            std::vector<double> reruns;
            int executed = 0;
            for (int r = 0; r < runs + 2; ++r) {  // a whole frame, one warm-up change, then runs
                test::MemorySink sink;
                const FrameReport rep =
                    executePlan(plans[r % 2], cap->source, sink, {}, nullptr, &cache);
                if (r >= 2) {
                    reruns.push_back(rep.seconds);
                    executed = rep.executedSteps;
                }
            }
            std::cout << fmt::format("{}: workbench re-run after r.SSGI.Quality changes: {:.3f} ms "
                                     "(median of {}; {} of {} passes executed; {})\n",
                                     device, median(reruns) * 1e3, runs, executed,
                                     plans[0].steps.size(),
                                     everyOutput ? "every pass output on the host"
                                                 : "only the shown output on the host");
            result[device][everyOutput ? "everyOutputRerunSeconds" : "workbenchRerunSeconds"] =
                median(reruns);
        }
    if (!jsonPath.empty())
        std::ofstream(jsonPath) << result.dump(2) << "\n";
    return 0;
}

}  // namespace

TEST_CASE("gpu: the check's chain runs on the CPU, with every figure it compares") {
    // Runs without a GPU too, so a machine without one still checks the chain the GPU cases use.
    auto cap = captureScene("glossy", {64, 48}, 1);
    for (const bool halfRes : {false, true}) {
        test::MemorySink sink;
        const FrameReport r = executePlan(chainPlan({.dumps = {"all"}, .errors = true,
                                                     .reflections = true,
                                                     .quality = halfRes ? 1 : 4,
                                                     .halfRes = halfRes,
                                                     .lights = lightsOf(cap->scene.scene),
                                                     .traversal = halfRes ? "bvh" : ""}),
                                          cap->source, sink);
        CHECK(sink.layers.count("deferred_lighting_ceiling.color") == 1);
        CHECK(sink.layers.count("camera_velocity.velocity") == 1);
        CHECK(sink.layers.count("oracle.specular") == 1);
        int figures = 0;
        for (const auto& p : r.passes)
            figures += int(p.metrics.size());
        CHECK(figures >= 2 * 7);
        CHECK(sink.layers.count("gi_vs_color.heat") == 1);
        CHECK(sink.layers.count("display.image") == 1);
        CHECK(sink.layers.at("ssgi.diffuse").image().width() == (halfRes ? 32 : 64));
        // The glossy floor and sphere reflect something on screen.
        double coverage = 0;
        const Plane& alpha = sink.layers.at("ssr.reflection").image().plane(3);
        for (int y = 0; y < alpha.height(); ++y)
            for (int x = 0; x < alpha.width(); ++x) coverage += alpha.at(x, y);
        CHECK(coverage > 1.0);
        CHECK(sink.layers.count("hybrid_reflections.reflection") == 1);
        CHECK(sink.layers.count("hybrid.diffuse") == 1);
    }
    // The ray-traced preset as the GPU case plans it.
    test::MemorySink sink;
    executePlan(raytracedPlan("cpu", "bvh", lightsOf(cap->scene.scene)), cap->source, sink);
    CHECK(sink.layers.count("ao_denoise.ao") == 1);
    CHECK(sink.layers.count("reflection_denoise.reflection") == 1);
    REQUIRE(sink.layers.count("rt_global_illumination.diffuse") == 1);
    CHECK(sink.layers.at("rt_global_illumination.diffuse").image().width() == 32);  // 50 %
    CHECK(sink.layers.at("gi_denoise.diffuse").image().width() == 64);
}

TEST_CASE("gpu: the chain on the GPU matches the CPU on the Cornell capture") {
    if (skipWithoutGpu())
        return;
    const auto diffs = runBoth("cornell", {256, 256});
    printDifferences("Cornell 256×256, frames 1–3", diffs);
    checkAgreement(diffs);
}

TEST_CASE("gpu: the chain on the GPU matches the CPU on the hard capture") {
    if (skipWithoutGpu())
        return;
    const auto diffs = runBoth("hard", {256, 192});
    printDifferences("hard 256×192, frames 1–3", diffs);
    checkAgreement(diffs);
}

TEST_CASE("gpu: the chain with SSR on the GPU matches the CPU on the glossy capture") {
    if (skipWithoutGpu())
        return;
    const auto diffs = runBoth("glossy", {256, 192});
    printDifferences("glossy 256×192, frames 1–3", diffs);
    checkAgreement(diffs);
}

TEST_CASE("gpu: the display through Unreal's filmic tonemapper on the GPU matches the CPU") {
    if (skipWithoutGpu())
        return;
    const auto diffs = runBoth("glossy", {256, 192}, 4, false, true);
    printDifferences("glossy 256×192, display ue4.27-film, frames 1–3", diffs);
    checkAgreement(diffs);
}

TEST_CASE("gpu: quality 1 at half resolution on the GPU matches the CPU (8 pixels a warp)") {
    if (skipWithoutGpu())
        return;
    const auto diffs = runBoth("cornell", {250, 190}, 1, true);
    printDifferences("Cornell 250×190, r.SSGI.Quality 1, half resolution, frames 1–3", diffs);
    checkAgreement(diffs);
}

// The captures the ray-traced cases compare on, each at a size whose texels a 50 % trace covers.
const std::vector<std::pair<std::string, Extent>> kRaytracedCaptures = {
    {"cornell", {256, 256}}, {"glossy", {256, 192}}, {"hard", {256, 192}}};

// The ray-traced preset: rt_global_illumination (at the preset's 50 % screen percentage),
// rt_ambient_occlusion and rt_reflections, the signal denoisers (gi_denoise's upscaling
// reconstruction too) and every other kernel of the chain, frames 1–3 with their histories, on
// the three captures.
TEST_CASE("gpu: the ray-traced preset on the GPU matches the CPU on the Cornell, glossy and hard captures") {
    if (skipWithoutGpu())
        return;
    for (const auto& [scene, extent] : kRaytracedCaptures) {
        const auto diffs = runRaytraced(scene, extent);
        printDifferences(fmt::format("ray-traced preset, {} {}×{}, frames 1–3", scene, extent.width,
                                     extent.height),
                         diffs);
        checkAgreement(diffs, 0);
        bool denoised = false;
        for (const auto& d : diffs.layers)
            denoised |= d.layer.find("gi_denoise.diffuse") != std::string::npos;
        CHECK(denoised);
    }
}

// rt_global_illumination past its first bounce: 4 paths of 3 bounces a texel (the preset traces
// 4 of 1), each texel's paths drawn from its stream one after another as forEachInSteps'
// steps; on the three captures.
TEST_CASE("gpu: rt_global_illumination's paths of 3 bounces, 4 a texel, match the CPU") {
    if (skipWithoutGpu())
        return;
    for (const auto& [scene, extent] : kRaytracedCaptures) {
        const auto diffs =
            runRaytraced(scene, extent, {{"samplesPerPixel", 4}, {"maxBounces", 3}});
        printDifferences(fmt::format("4 GI paths of 3 bounces, {} {}×{}, frames 1–3", scene,
                                     extent.width, extent.height),
                         diffs);
        checkAgreement(diffs, 0);
        int gi = 0;
        for (const auto& d : diffs.layers)
            gi += d.layer.find("rt_global_illumination.diffuse") != std::string::npos;
        CHECK(gi >= 3);  // compared in every frame
    }
}

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--bench") == 0) {
            std::string scene = "cornell", json, config;
            Extent extent{1920, 1080};
            int runs = 10;
            for (int j = 1; j < argc; ++j) {
                const std::string a = argv[j];
                const char* v = j + 1 < argc ? argv[j + 1] : "";
                if (a == "--scene")
                    scene = v;
                else if (a == "--size" && std::sscanf(v, "%dx%d", &extent.width, &extent.height) != 2)
                    return std::cerr << "--size WxH\n", 2;
                else if (a == "--runs")
                    runs = std::max(1, std::atoi(v));
                else if (a == "--json")
                    json = v;
                else if (a == "--config")
                    config = v;
            }
            try {
                return bench(scene, extent, runs, json, config);
            } catch (const std::exception& e) {
                std::cerr << "framepass_gpu_check: " << e.what() << "\n";
                return 1;
            }
        }
    doctest::Context context(argc, argv);
    const int failed = context.run();
    // Without a GPU the comparisons skipped: exit 77, ctest's SKIP_RETURN_CODE
    // (tests/CMakeLists.txt), so the suite reads "Skipped", not "Passed".
    if (failed == 0 && !context.shouldExit() && !cuda::unavailableReason().empty()) {
        std::cout << "skipped: " << cuda::unavailableReason() << "\n";
        return 77;
    }
    return failed;
}
