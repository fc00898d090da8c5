#include "app/PlanReport.h"

#include "app/Invocation.h"
#include "foundation/Cuda.h"

#include <fmt/ranges.h>

#include <set>

namespace fp::app {

namespace {

std::string dotQuoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    return out + "\"";
}

// One parameter value as plan prints it: numbers and booleans bare, text quoted.
std::string paramText(const nlohmann::json& v) {
    if (v.is_number_float()) return fmt::format("{:g}", v.get<double>());
    return v.dump();
}

}  // namespace

std::string planDot(const Plan& plan) {
    std::string d = "digraph framepass {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n";
    std::set<std::string> buffers;
    for (const auto& s : plan.steps)
        for (const auto& [port, ref] : s.inputs)
            if (ref.fromCapture) buffers.insert(ref.buffer);
    for (const auto& b : buffers)
        d += fmt::format("  {} [shape=ellipse, style=filled, fillcolor=\"#f2e6c9\", label={}];\n",
                         dotQuoted("capture:" + b), dotQuoted(b));
    for (const auto& s : plan.steps) {
        std::vector<std::string> ins, outs;
        for (const auto& [port, ref] : s.inputs) ins.push_back("<in_" + port + "> " + port);
        for (const auto& o : s.io.outputs)
            if (s.requestedOutputs.count(o.name)) outs.push_back("<out_" + o.name + "> " + o.name);
        const bool gpu = s.device == Device::Cuda;
        d += fmt::format("  {} [shape=record, style=filled, fillcolor=\"{}\", label=\"{{{{{}}}|{} "
                         "({}){}|{{{}}}}}\"];\n",
                         dotQuoted(s.name), gpu ? "#cdebc5" : "#cfe0f3", fmt::join(ins, "|"),
                         s.name, s.type, gpu ? " GPU" : "", fmt::join(outs, "|"));
        for (const auto& [port, ref] : s.inputs) {
            const std::string from = ref.fromCapture
                                         ? dotQuoted("capture:" + ref.buffer)
                                         : dotQuoted(plan.steps[std::size_t(ref.step)].name) +
                                               ":" + dotQuoted("out_" + ref.port);
            d += fmt::format("  {} -> {}:{};\n", from, dotQuoted(s.name), dotQuoted("in_" + port));
        }
    }
    for (const auto& o : plan.outputs) {
        d += fmt::format("  {} [shape=note, label={}];\n", dotQuoted("file:" + o.file),
                         dotQuoted(o.file));
        for (const auto& src : o.sources) {
            const auto dot = src.find('.');
            if (src.rfind("capture:", 0) == 0 || dot == std::string::npos) continue;
            d += fmt::format("  {}:{} -> {} [style=dashed];\n", dotQuoted(src.substr(0, dot)),
                             dotQuoted("out_" + src.substr(dot + 1)), dotQuoted("file:" + o.file));
        }
    }
    for (const auto& c : plan.culled)
        d += fmt::format("  {} [shape=box, style=\"filled,dashed\", fillcolor=\"#e6e6e6\", "
                         "fontcolor=\"#808080\", label={}];\n",
                         dotQuoted(c.name), dotQuoted(c.name + " (" + c.type + ")\nculled: " + c.reason));
    return d + "}\n";
}

nlohmann::json planJson(const RunSetup& session, const std::string& config) {
    const Plan& plan = session.plan();
    nlohmann::json j = plan.toJson(session.extent());
    j["config"] = config;
    j["capture"] = session.config().capture;
    j["frames"] = session.frames();
    j["profile"] = session.profile().name();
    const auto files = session.openCapture(
        session.frames().empty() ? "" : session.capturePath(session.frames().front()));
    // plan works before a capture exists (a farm plans first), but says that it does not.
    j["captureOnDisk"] = bool(files);
    if (!files)
        logWarning(fmt::format(
            "the capture {} is not on disk: its channels are not checked and peak memory is "
            "not known; 'framepass run' would stop here",
            session.frames().empty() ? session.config().capture
                                     : session.capturePath(session.frames().front())));
    for (auto& r : j["captureReads"])
        r["channels"] = files ? files->describe(r["buffer"].get<std::string>())
                              : std::vector<std::string>{"(capture not on disk yet)"};
    return j;
}

std::string planText(const RunSetup& session, const std::string& config,
                     const nlohmann::json& j) {
    const Plan& plan = session.plan();
    std::string out;
    out += fmt::format("plan for {} ({} frame{}, capture {})\n", config,
                             session.frames().size(), session.frames().size() == 1 ? "" : "s",
                             session.config().capture);
    for (const auto& t : plan.templates)
        out += fmt::format("  {} expands for light{} {}: {}\n", t.pointer,
                                 t.lights.size() == 1 ? "" : "s", fmt::join(t.lights, ", "),
                                 fmt::join(t.passes, ", "));
    int i = 1;
    for (const auto& s : plan.steps) {
        std::vector<std::string> ins;
        for (const auto& [port, ref] : s.inputs)
            ins.push_back(port + "←" + ref.key);
        out += fmt::format("  {}. {} ({}){}  in: {}  out: {}\n", i++, s.name, s.type,
                                 plan.device == Device::Cuda
                                     ? (s.device == Device::Cuda ? " [gpu]" : " [cpu]")
                                     : "",
                                 fmt::join(ins, ", "), fmt::join(s.requestedOutputs, ", "));
        std::vector<std::string> params;
        for (const auto& [k, v] : s.params.items()) params.push_back(k + "=" + paramText(v));
        if (!params.empty())
            out += fmt::format("       params: {}\n", fmt::join(params, " "));
    }
    if (plan.device == Device::Cuda) {
        const std::string why = cuda::unavailableReason();
        out += fmt::format("device: cuda ({}); [cpu] passes have no CUDA kernel, and "
                                 "images cross only where a pass on the other side reads "
                                 "them\n",
                                 why.empty() ? cuda::deviceName() : "not usable here: " + why);
    }
    out += "reads:\n";
    for (const auto& r : j["captureReads"])
        out += fmt::format("  {:<16} {}\n", r["buffer"].get<std::string>(),
                                 fmt::join(r["channels"].get<std::vector<std::string>>(), " "));
    out += "writes:\n";
    for (const auto& o : plan.outputs)
        out += fmt::format("  {:<28} ← {}\n", o.file, fmt::join(o.sources, ", "));
    if (session.extent().width > 0)
        out += fmt::format("peak memory: {:.1f} MiB at {}×{}\n",
                                 plan.estimatePeakBytes(session.extent()) / 1048576.0,
                                 session.extent().width, session.extent().height);
    out += fmt::format("geometry: {}\n", plan.needsScene ? "loaded (a pass traces rays)"
                                               : plan.needsLights ? "not needed (lights only)"
                                                                  : "not needed");
    for (const auto& c : plan.culled)
        out += fmt::format("culled: {} ({}): {}\n", c.name, c.type, c.reason);
    return out;
}

std::vector<int> upstreamSteps(const Plan& plan, const SourceRef& source) {
    std::set<int> needed;
    std::vector<int> open;
    if (!source.fromCapture && source.step >= 0) open.push_back(source.step);
    while (!open.empty()) {
        const int s = open.back();
        open.pop_back();
        if (!needed.insert(s).second) continue;
        for (const auto& [port, ref] : plan.steps[std::size_t(s)].inputs)
            if (!ref.fromCapture && ref.step >= 0) open.push_back(ref.step);
    }
    std::vector<int> out;
    for (const int s : needed)
        if (!plan.steps[std::size_t(s)].io.roles.measuresError) out.push_back(s);
    return out;
}

}  // namespace fp::app
