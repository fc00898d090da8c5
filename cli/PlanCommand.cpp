// framepass plan: the resolved graph, without reading a pixel.
#include "cli/Commands.h"
#include "cli/Invocation.h"
#include "cli/RunSession.h"
#include "passes/core/Cuda.h"

#include <iostream>

namespace fp::cli {

Command addPlanCommand(CLI::App& app) {
    struct Options {
        SessionOptions session;
        bool json = false;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand("plan",
                                       "show the resolved pass graph in order, the capture "
                                       "channels it reads, peak memory and culled passes");
    opt->session.addTo(*sub);
    sub->add_flag("--json", opt->json, "machine-readable output");

    return [opt]() {
        const RunSession session(opt->session);
        const Plan& plan = session.plan();
        for (const auto& w : plan.warnings)
            logWarning(fmt::format("{}: {}", w.pointer, w.message));
        nlohmann::json j = plan.toJson(session.extent());
        j["config"] = opt->session.config;
        j["capture"] = session.config().capture;
        j["frames"] = session.frames();
        j["profile"] = session.profile().name();
        const auto files = session.openCapture(
            session.frames().empty() ? "" : session.capturePath(session.frames().front()));
        for (auto& r : j["captureReads"])
            r["channels"] = files ? files->describe(r["buffer"].get<std::string>())
                                  : std::vector<std::string>{"(capture not on disk yet)"};
        if (opt->json) {
            std::cout << j.dump(2) << "\n";
            return 0;
        }
        std::cout << fmt::format("plan for {} ({} frame{}, capture {})\n", opt->session.config,
                                 session.frames().size(), session.frames().size() == 1 ? "" : "s",
                                 session.config().capture);
        for (const auto& t : plan.templates)
            std::cout << fmt::format("  {} expands for light{} {}: {}\n", t.pointer,
                                     t.lights.size() == 1 ? "" : "s", fmt::join(t.lights, ", "),
                                     fmt::join(t.passes, ", "));
        int i = 1;
        for (const auto& s : plan.steps) {
            std::vector<std::string> ins;
            for (const auto& [port, ref] : s.inputs)
                ins.push_back(port + "←" + ref.key);
            std::cout << fmt::format("  {}. {} ({}){}  in: {}  out: {}\n", i++, s.name, s.type,
                                     plan.device == Device::Cuda
                                         ? (s.device == Device::Cuda ? " [gpu]" : " [cpu]")
                                         : "",
                                     fmt::join(ins, ", "), fmt::join(s.requestedOutputs, ", "));
        }
        if (plan.device == Device::Cuda) {
            const std::string why = cuda::unavailableReason();
            std::cout << fmt::format("device: cuda ({}); [cpu] passes have no CUDA kernel, and "
                                     "images cross only where a pass on the other side reads "
                                     "them\n",
                                     why.empty() ? cuda::deviceName() : "not usable here: " + why);
        }
        std::cout << "reads:\n";
        for (const auto& r : j["captureReads"])
            std::cout << fmt::format("  {:<16} {}\n", r["buffer"].get<std::string>(),
                                     fmt::join(r["channels"].get<std::vector<std::string>>(), " "));
        std::cout << "writes:\n";
        for (const auto& o : plan.outputs)
            std::cout << fmt::format("  {:<28} ← {}\n", o.file, fmt::join(o.sources, ", "));
        if (session.extent().width > 0)
            std::cout << fmt::format("peak memory: {:.1f} MiB at {}×{}\n",
                                     plan.estimatePeakBytes(session.extent()) / 1048576.0,
                                     session.extent().width, session.extent().height);
        std::cout << fmt::format("geometry: {}\n", plan.needsScene ? "loaded (a pass traces rays)"
                                                   : plan.needsLights ? "not needed (lights only)"
                                                                      : "not needed");
        for (const auto& c : plan.culled)
            std::cout << fmt::format("culled: {} ({}): {}\n", c.name, c.type, c.reason);
        return 0;
    };
}

}  // namespace fp::cli
