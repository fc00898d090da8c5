// capture: render a canonical capture (GBuffer, lighting, previous frame) from a scene.
#include "app/Capture.h"

#include "app/Invocation.h"
#include "app/TruthDefinitions.h"
#include "io/ExrWriter.h"
#include "io/FramePattern.h"
#include "io/SafeFiles.h"
#include "io/scene/SceneLoader.h"
#include "reference/GBufferRenderer.h"
#include "foundation/Error.h"
#include "framework/SemanticBuffers.h"
#include "metrics/ErrorMetrics.h"
#include "reference/TruthRenderer.h"

#include <chrono>
#include <filesystem>
#include <cmath>
#include <limits>
#include <iostream>

namespace fp::app {

void captureScene(const CaptureOptions& opt, std::ostream& out) {
    const io::SceneFile sf = io::loadScene(opt.scene);
    Extent extent = sf.resolution;
    if (opt.width) extent.width = opt.width;
    if (opt.height) extent.height = opt.height;
    const std::vector<int> frames = opt.frames.empty() ? std::vector<int>{int(opt.frame)}
                                                        : io::parseFrameSpec(opt.frames);
    const io::FramePattern pattern(opt.output);
    if (frames.size() > 1 && !pattern.hasFrameToken())
        throw UsageError(fmt::format("-o {}: several frames need a frame token (#### or %04d)",
                                     opt.output));
    // Never over the scene it reads: its JSON, its geometry, an OBJ's material library.
    const std::vector<std::string> inputs = {
        opt.scene, sf.geometryFile(),
        std::filesystem::path(sf.geometryFile()).replace_extension(".mtl").string()};
    for (int frame : frames) {
        io::refuseToOverwriteInputs(pattern.path(frame), inputs, "-o");
        io::checkWritable(pattern.path(frame), "-o");
    }
    auto seconds = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    const std::string fingerprint = io::sceneFingerprint(sf);
    int lastProgress = -1;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const int frame = frames[i];
        const auto t0 = std::chrono::steady_clock::now();
        const FrameCamera camera = sf.cameraForFrame(frame, extent);
        CaptureSettings settings;
        settings.frame = frame;
        settings.lightSamples = opt.lightSamples;
        const CaptureResult result = GBufferRenderer(sf.scene, camera, settings).render();
        const double gbufferSeconds = seconds(t0);
        // One EXR part per buffer: a reader decodes only the parts of the buffers it needs
        // (in a single-part file every read would decompress every channel).
        std::vector<io::ExrPart> parts;
        for (const auto& b : semanticBuffers()) {
            const bool half = opt.half && !(isDepthBuffer(b.name) && opt.floatDepth);
            parts.push_back({b.name, {{b.name, &result.buffers.at(b.name), half}}});
        }
        io::ExrMetadata meta;
        meta.camera = camera;
        meta.frame = frame;
        // The scene, relative to the capture, and its fingerprint: a run whose chain traces rays
        // and whose config names no scene takes this one (RunSetup).
        meta.strings["framepass:scene"] =
            std::filesystem::absolute(opt.scene)
                .lexically_proximate(std::filesystem::absolute(pattern.path(frame)).parent_path())
                .string();
        meta.strings["framepass:sceneFingerprint"] = fingerprint;
        meta.strings["framepass:software"] = "framepass capture";
        if (opt.half)
            meta.strings["framepass:storage"] = opt.floatDepth ? "half, depth float32" : "half";

        auto progress = [&](double within) {
            const int pct = int(100.0 * (double(i) + within) / double(frames.size()));
            if (pct / 10 > lastProgress / 10 || (pct == 100 && lastProgress != 100)) {
                logProgress(pct);
                lastProgress = pct;
            }
        };
        TruthResult truth;
        std::string truthLine;
        if (opt.truth) {
            TruthSettings ts;
            ts.frame = frame;
            ts.samplesPerPixel = opt.truthSpp;
            ts.aoRadius = opt.aoRadiusMeters * sf.scene.sceneUnitsPerMeter;
            const auto tt = std::chrono::steady_clock::now();
            truth = TruthRenderer(sf.scene, camera, ts).render([&](int done, int total) {
                progress(double(done) / total);
            });
            const double st = seconds(tt);
            truthLine = fmt::format("; truth {} spp in {:.2f} s ({:.2f} Mrays/s)", opt.truthSpp,
                                    st, truth.rays / st * 1e-6);
            // How noisy the reference is, layer by layer, over the pixels that are not sky.
            const Image mask = notSkyMask(result.buffers.at("SceneDepth"),
                                          std::numeric_limits<float>::infinity());
            for (const auto& name : truth.names) {
                for (const std::string& layer : {name, name + ".StdErr"})
                    parts.push_back({layer, {{layer, &truth.layers.at(layer), false}}});
                if (name == "Truth.ReflectedEmitter") {
                    // A mask, not a light: say how many pixels it holds.
                    const Plane& f = truth.layers.at(name).plane(0);
                    int64_t seen = 0;
                    for (int y = 0; y < f.height(); ++y)
                        for (int x = 0; x < f.width(); ++x) seen += f.at(x, y) > 0.0f;
                    truthLine += fmt::format("\n  {:<34} {} pixels reflect an emitter (compare "
                                             "--mask reflected-emitter leaves them out)",
                                             name, seen);
                    continue;
                }
                const double rel = medianRelativeStdErr(
                    truth.layers.at(name), truth.layers.at(name + ".StdErr"), &mask);
                truthLine += fmt::format("\n  {:<34} median relative standard error {}", name,
                                         std::isnan(rel) ? std::string("— (all zero)")
                                                         : fmt::format("{:.2f} %", 100.0 * rel));
            }
            meta.strings["framepass:truthSamplesPerPixel"] = std::to_string(opt.truthSpp);
            // What each truth measures (its AO radius, its bounces): a measure or compare
            // against a layer of another definition says so (app/TruthDefinitions.h).
            for (const auto& [name, value] : truthDefinitionAttributes(ts.aoRadius, ts.maxBounces))
                meta.strings[name] = value;
        }
        const std::string path = pattern.path(frame);
        io::writeExr(path, parts, meta);
        out << fmt::format("wrote {} ({}×{}, {} parts, frame {}) in {:.2f} s: GBuffer {} "
                                 "primary + {} shadow rays in {:.2f} s ({:.2f} Mrays/s){}\n",
                                 path, extent.width, extent.height, parts.size(), frame,
                                 seconds(t0), result.primaryRays, result.shadowRays,
                                 gbufferSeconds,
                                 (result.primaryRays + result.shadowRays) / gbufferSeconds * 1e-6,
                                 truthLine);
        progress(1.0);
    }
}

}  // namespace fp::app
