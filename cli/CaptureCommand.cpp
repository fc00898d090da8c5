// framepass capture: render a canonical capture (GBuffer, lighting, previous frame) from a scene.
#include "cli/Commands.h"
#include "io/ExrWriter.h"
#include "io/FramePattern.h"
#include "io/SceneLoader.h"
#include "passes/capture/GBufferRenderer.h"
#include "passes/core/Error.h"
#include "passes/core/SemanticBuffers.h"

#include <chrono>
#include <iostream>

namespace fp::cli {

Command addCaptureCommand(CLI::App& app) {
    struct Options {
        std::string scene, output, frames;
        int width = 0, height = 0, lightSamples = 16;
        int64_t frame = 1;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand(
        "capture", "render a canonical capture (every GBuffer buffer, SceneColor, previous frame, "
                   "velocity) from a scene JSON");
    sub->add_option("scene", opt->scene, "scene JSON naming a .gltf/.glb/.obj")->required();
    sub->add_option("-o,--output", opt->output, "output EXR (#### / %04d for sequences)")->required();
    sub->add_option("--width", opt->width, "width in pixels (default: the scene's resolution)")
        ->check(CLI::Range(1, 16384));
    sub->add_option("--height", opt->height, "height in pixels")->check(CLI::Range(1, 16384));
    auto* frameOpt = sub->add_option("--frame", opt->frame, "frame number (moves the camera by "
                                                             "cameraMotion; seeds sampling)");
    sub->add_option("--frames", opt->frames, "frame spec for a sequence, e.g. 1-6")
        ->excludes(frameOpt);
    sub->add_option("--light-samples", opt->lightSamples,
                    "shadow samples per pixel for lights with size")
        ->check(CLI::Range(1, 4096));

    return [opt]() {
        const io::SceneFile sf = io::loadScene(opt->scene);
        Extent extent = sf.resolution;
        if (opt->width) extent.width = opt->width;
        if (opt->height) extent.height = opt->height;
        const std::vector<int> frames = opt->frames.empty() ? std::vector<int>{int(opt->frame)}
                                                            : io::parseFrameSpec(opt->frames);
        const io::FramePattern pattern(opt->output);
        if (frames.size() > 1 && !pattern.hasFrameToken())
            throw UsageError(fmt::format("-o {}: several frames need a frame token (#### or %04d)",
                                         opt->output));
        for (std::size_t i = 0; i < frames.size(); ++i) {
            const int frame = frames[i];
            const auto t0 = std::chrono::steady_clock::now();
            const FrameCamera camera = sf.cameraForFrame(frame, extent);
            CaptureSettings settings;
            settings.frame = frame;
            settings.lightSamples = opt->lightSamples;
            const CaptureResult result = GBufferRenderer(sf.scene, camera, settings).render();
            // One EXR part per buffer: a reader decodes only the parts of the buffers it needs
            // (in a single-part file every read would decompress every channel).
            std::vector<io::ExrPart> parts;
            for (const auto& b : semanticBuffers())
                parts.push_back({b.name, {{b.name, &result.buffers.at(b.name), false}}});
            io::ExrMetadata meta;
            meta.camera = camera;
            meta.frame = frame;
            meta.strings["framepass:scene"] = opt->scene;
            meta.strings["framepass:software"] = "framepass capture";
            const std::string path = pattern.path(frame);
            io::writeExr(path, parts, meta);
            const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::cout << fmt::format("wrote {} ({}×{}, {} buffers, frame {}) in {:.2f} s: {} primary "
                                     "+ {} shadow rays ({:.2f} Mrays/s)\n",
                                     path, extent.width, extent.height, parts.size(), frame, s,
                                     result.primaryRays, result.shadowRays,
                                     (result.primaryRays + result.shadowRays) / s * 1e-6);
            if (frames.size() > 1)
                std::cout << fmt::format("Progress: {}%\n", int(100 * (i + 1) / frames.size()));
        }
        return 0;
    };
}

}  // namespace fp::cli
