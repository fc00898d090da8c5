#include "passes/core/Planner.h"

#include "passes/core/CvarTable.h"
#include "passes/core/SemanticBuffers.h"
#include "passes/core/Suggest.h"

#include <algorithm>
#include <functional>
#include <queue>

namespace fp {

namespace {

struct NodeState {
    const NodeDesc* desc = nullptr;
    const PassType* type = nullptr;
    std::shared_ptr<Pass> pass;
    PassIO io;
    nlohmann::json params;
    std::map<std::string, SourceRef> inputs;
    std::map<std::string, std::string> inputPointers;  // port → where its binding came from
    bool live = false;
};

const PortSpec* findPort(const std::vector<PortSpec>& ports, const std::string& name) {
    for (const auto& p : ports)
        if (p.name == name)
            return &p;
    return nullptr;
}

std::vector<std::string> portNames(const std::vector<PortSpec>& ports) {
    std::vector<std::string> n;
    for (const auto& p : ports)
        n.push_back(p.name);
    return n;
}

std::vector<std::string> captureBufferNames() {
    std::vector<std::string> n;
    for (const auto& b : semanticBuffers())
        n.push_back(b.name);
    return n;
}

// Validates one layer of parameter values (cvars, config or --set) and reports its errors at
// `where`, which names the place the user typed them.
void validateLayer(const PassType& type,
                   const nlohmann::json& layer,
                   const std::string& pointer,
                   const std::string& where,
                   const std::string& context,
                   Diagnostics& diag) {
    Diagnostics local;
    nlohmann::json resolved;
    type.create(layer, pointer, local, resolved);
    for (const auto& e : local.errors())
        diag.error(where.empty() ? e.pointer : where,
                   context.empty() ? e.message : e.message + " (" + context + ")");
}

}  // namespace

Plan makePlan(const GraphDesc& graph, const PassRegistry& registry, const PlanInputs& in) {
    Diagnostics diag;
    for (const auto& e : in.priorErrors)
        diag.error(e.pointer, e.message);
    Plan plan;
    const CvarTable cvarTable(registry);
    std::vector<NodeState> nodes(graph.nodes.size());
    std::map<std::string, int> nodeIndex;

    // --- names and types ---------------------------------------------------------------------
    for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
        const NodeDesc& d = graph.nodes[i];
        nodes[i].desc = &d;
        if (d.name.empty() || d.name.find_first_of(".:/ ") != std::string::npos)
            diag.error(d.pointer + "/name",
                       fmt::format("pass name '{}' must be non-empty without '.', ':', '/' or "
                                   "spaces",
                                   d.name));
        else if (!nodeIndex.emplace(d.name, int(i)).second)
            diag.error(d.pointer + "/name", fmt::format("pass name '{}' is used twice", d.name));
        nodes[i].type = registry.find(d.type);
        if (!nodes[i].type)
            diag.error(d.pointer + "/type", fmt::format("unknown pass type '{}'{}", d.type,
                                                        didYouMean(d.type, registry.ids())));
    }
    std::vector<std::string> allNames;
    for (const auto& d : graph.nodes)
        allNames.push_back(d.name);

    // --- cvars: config first, then --cvar ------------------------------------------------------
    struct CvarValue {
        nlohmann::json value;
        std::string where;
    };
    std::map<std::string, CvarValue> cvars;
    for (const auto& [k, v] : graph.cvars.items())
        cvars[k] = {v, "/cvars/" + jsonPointerEscape(k)};
    for (const auto& [k, v] : in.overrides.cvars.items())
        cvars[k] = {v, "--cvar " + k};
    for (const auto& [name, cv] : cvars) {
        const CvarMapping* m = cvarTable.find(name);
        if (!m) {
            diag.warning(cv.where, fmt::format("unknown cvar '{}' is ignored{}", name,
                                               didYouMean(name, cvarTable.names())));
        } else if (m->passType.empty() && cv.value == m->emulatedValue) {
            // The value the chain emulates: nothing to say.
        } else if (m->passType.empty()) {
            diag.warning(cv.where,
                         fmt::format("cvar '{}' is not emulated by framepass ({})", name, m->note));
        } else if (const auto types = cvarTable.targets(name);
                   std::none_of(graph.nodes.begin(), graph.nodes.end(), [&](const NodeDesc& d) {
                       return std::find(types.begin(), types.end(), d.type) != types.end();
                   })) {
            diag.warning(cv.where, fmt::format("cvar '{}' sets {}.{}, but the chain has no '{}' "
                                               "pass",
                                               name, m->passType, m->param, m->passType));
        }
    }

    // --- --set PASS.PARAM=VALUE ---------------------------------------------------------------
    std::map<int, nlohmann::json> setLayers;
    std::map<int, std::vector<std::string>> setWhere;
    for (const auto& [target, value] : in.overrides.sets) {
        const std::string where = "--set " + target;
        auto dot = target.find('.');
        if (dot == std::string::npos) {
            diag.error(where, "expected PASS.PARAM=VALUE");
            continue;
        }
        std::string pass = target.substr(0, dot), param = target.substr(dot + 1);
        auto it = nodeIndex.find(pass);
        if (it == nodeIndex.end()) {
            diag.error(where,
                       fmt::format("no pass named '{}'{}", pass, didYouMean(pass, allNames)));
            continue;
        }
        setLayers[it->second][param] = value;
        setWhere[it->second].push_back(where);
    }

    // --- instantiate: defaults ← cvars ← config params ← --set --------------------------------
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        NodeState& n = nodes[i];
        if (!n.type)
            continue;
        const std::string paramsPtr = n.desc->pointer + "/params";
        const std::size_t errorsBefore = diag.errors().size();
        nlohmann::json merged = nlohmann::json::object();
        for (const auto& [name, cv] : cvars) {
            const CvarMapping* m = cvarTable.find(name, n.desc->type);
            if (!m)
                continue;
            nlohmann::json layer = {{m->param, cv.value}};
            validateLayer(*n.type, layer, paramsPtr, cv.where,
                          fmt::format("cvar {} sets {}.{}", name, n.desc->name, m->param), diag);
            merged[m->param] = cv.value;
        }
        validateLayer(*n.type, n.desc->params, paramsPtr, "", "", diag);
        if (n.desc->params.is_object())
            for (const auto& [k, v] : n.desc->params.items())
                merged[k] = v;
        if (setLayers.count(int(i))) {
            validateLayer(*n.type, setLayers[int(i)], paramsPtr, setWhere[int(i)].front(), "",
                          diag);
            for (const auto& [k, v] : setLayers[int(i)].items())
                merged[k] = v;
        }
        // Every layer was validated above. With errors, the pass is still made from its
        // defaults so that its ports can be checked too: all problems come out in one round.
        Diagnostics ignored;
        const bool paramsOk = diag.errors().size() == errorsBefore;
        n.pass = n.type->create(paramsOk ? merged : nlohmann::json::object(), paramsPtr, ignored,
                                n.params);
        n.io = n.pass->describe();
    }

    // --- bind inputs ---------------------------------------------------------------------------
    // Returns false (with an error) when `text` does not name an existing source.
    auto resolveSource = [&](const std::string& text, const std::string& where, int wantChannels,
                             SourceRef& ref) -> bool {
        ref = {};
        ref.key = text;
        if (text.rfind("capture:", 0) == 0) {
            ref.fromCapture = true;
            ref.buffer = text.substr(8);
            if (const SemanticBuffer* b = findSemanticBuffer(ref.buffer)) {
                ref.kind = b->kind;
                ref.channels = int(b->channels.size());
            } else if (isTruthBuffer(ref.buffer)) {
                // Truth layers are data: a reference is compared as stored, never converted.
                ref.kind = PortKind::Data;
                auto known = in.truthChannels.find(ref.buffer);
                ref.channels = known != in.truthChannels.end()
                                   ? known->second
                                   : (wantChannels > 0 ? wantChannels : 3);
            } else {
                diag.error(where, fmt::format("unknown capture buffer '{}'{}", ref.buffer,
                                              didYouMean(ref.buffer, captureBufferNames())));
                return false;
            }
        } else {
            auto dot = text.find('.');
            if (dot == std::string::npos) {
                diag.error(where,
                           fmt::format("'{}' should be 'capture:Buffer' or 'pass.port'", text));
                return false;
            }
            std::string pass = text.substr(0, dot);
            ref.port = text.substr(dot + 1);
            auto it = nodeIndex.find(pass);
            if (it == nodeIndex.end()) {
                diag.error(where,
                           fmt::format("no pass named '{}'{}", pass, didYouMean(pass, allNames)));
                return false;
            }
            ref.step = it->second;  // node index for now; remapped to step index below
            const NodeState& producer = nodes[it->second];
            if (!producer.pass)
                return false;  // its own errors are already reported
            const PortSpec* out = findPort(producer.io.outputs, ref.port);
            if (!out) {
                diag.error(
                    where,
                    fmt::format("pass '{}' ({}) has no output '{}'{}", pass, producer.desc->type,
                                ref.port, didYouMean(ref.port, portNames(producer.io.outputs))));
                return false;
            }
            ref.kind = out->kind;
            ref.channels = int(out->channels.size());
        }
        if (wantChannels > 0 && ref.channels != wantChannels) {
            diag.error(where,
                       fmt::format("'{}' has {} channel{}, the input needs {}", text, ref.channels,
                                   ref.channels == 1 ? "" : "s", wantChannels));
            return false;
        }
        return true;
    };

    std::vector<std::set<int>> dependsOn(nodes.size());
    std::vector<std::vector<std::string>> unboundRequired(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        NodeState& n = nodes[i];
        if (!n.pass)
            continue;
        for (const auto& [port, src] : n.desc->inputs)
            if (!findPort(n.io.inputs, port))
                diag.error(
                    n.desc->pointer + "/inputs/" + jsonPointerEscape(port),
                    fmt::format("pass '{}' ({}) has no input '{}'{}", n.desc->name, n.desc->type,
                                port, didYouMean(port, portNames(n.io.inputs))));
        for (const auto& port : n.io.inputs) {
            std::string text, where;
            if (auto it = n.desc->inputs.find(port.name); it != n.desc->inputs.end()) {
                text = it->second;
                where = n.desc->pointer + "/inputs/" + jsonPointerEscape(port.name);
            } else {
                text = port.captureDefault.empty() ? "" : "capture:" + port.captureDefault;
                where = n.desc->pointer;
            }
            if (text.empty()) {
                if (!port.optional)
                    unboundRequired[i].push_back(port.name);
                continue;
            }
            SourceRef ref;
            if (!resolveSource(text, where, int(port.channels.size()), ref))
                continue;
            if (!ref.fromCapture)
                dependsOn[i].insert(ref.step);
            n.inputs[port.name] = ref;
            n.inputPointers[port.name] = where;
        }
    }

    // --- roots: outputs and dumps ----------------------------------------------------------------
    plan.outputs = graph.outputs;
    std::vector<std::string> dumps = in.overrides.dumps;
    if (std::find(dumps.begin(), dumps.end(), "all") != dumps.end()) {
        dumps.erase(std::remove(dumps.begin(), dumps.end(), "all"), dumps.end());
        for (const auto& n : nodes)
            if (n.pass)
                for (const auto& o : n.io.outputs)
                    dumps.push_back(n.desc->name + "." + o.name);
    }
    for (const auto& d : dumps)
        plan.outputs.push_back({d + ".exr", {d}, "--dump " + d, true});

    std::set<int> roots;
    std::map<std::string, SourceRef> outputSources;
    for (const auto& out : plan.outputs)
        for (std::size_t k = 0; k < out.sources.size(); ++k) {
            SourceRef ref;
            std::string where =
                out.isDump ? out.pointer
                           : out.pointer + (out.sources.size() > 1 ? "/" + std::to_string(k) : "");
            if (!resolveSource(out.sources[k], where, 0, ref))
                continue;
            if (!ref.fromCapture)
                roots.insert(ref.step);
            outputSources[ref.key] = ref;
        }

    // --- cull: reverse reachability from the roots (Falcor resolveExecutionOrder) ---------------
    std::vector<int> stack(roots.begin(), roots.end());
    while (!stack.empty()) {
        int i = stack.back();
        stack.pop_back();
        if (nodes[i].live)
            continue;
        nodes[i].live = true;
        for (int j : dependsOn[i])
            stack.push_back(j);
    }
    for (const auto& n : nodes)
        if (!n.live && n.pass)
            plan.culled.push_back(
                {n.desc->name, n.desc->type,
                 roots.empty() ? "no outputs are requested" : "no requested output depends on it"});

    // --- live-only checks: required inputs, capture channels -------------------------------------
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const NodeState& n = nodes[i];
        if (!n.live)
            continue;
        for (const auto& port : unboundRequired[i])
            diag.error(n.desc->pointer + "/inputs",
                       fmt::format("required input '{}' of pass '{}' ({}) is not bound", port,
                                   n.desc->name, n.desc->type));
    }
    auto checkAvailable = [&](const SourceRef& ref, const std::string& where) {
        if (!ref.fromCapture || !in.availableBuffers)
            return;
        if (in.availableBuffers->count(ref.buffer))
            return;
        std::vector<std::string> have(in.availableBuffers->begin(), in.availableBuffers->end());
        diag.error(where, fmt::format("the capture has no '{}' buffer{}; it has [{}]", ref.buffer,
                                      didYouMean(ref.buffer, have), fmt::join(have, ", ")));
    };
    for (const auto& n : nodes)
        if (n.live)
            for (const auto& [port, ref] : n.inputs)
                checkAvailable(ref, n.inputPointers.at(port));
    for (const auto& out : plan.outputs)
        for (const auto& s : out.sources)
            if (auto it = outputSources.find(s); it != outputSources.end())
                checkAvailable(it->second, out.pointer);

    // --- order: Kahn, ties broken by declaration order; cycles reported with their path ---------
    std::vector<int> order;
    {
        std::vector<int> indegree(nodes.size(), 0);
        std::vector<std::vector<int>> users(nodes.size());
        for (std::size_t i = 0; i < nodes.size(); ++i)
            if (nodes[i].live)
                for (int j : dependsOn[i]) {
                    ++indegree[i];
                    users[j].push_back(int(i));
                }
        std::priority_queue<int, std::vector<int>, std::greater<int>> ready;
        for (std::size_t i = 0; i < nodes.size(); ++i)
            if (nodes[i].live && indegree[i] == 0)
                ready.push(int(i));
        while (!ready.empty()) {
            int i = ready.top();
            ready.pop();
            order.push_back(i);
            for (int u : users[i])
                if (--indegree[u] == 0)
                    ready.push(u);
        }
        std::size_t liveCount =
            std::count_if(nodes.begin(), nodes.end(), [](const NodeState& n) { return n.live; });
        if (order.size() != liveCount) {
            // Walk dependencies from a node left over until one repeats: that loop is the cycle.
            int start = -1;
            for (std::size_t i = 0; i < nodes.size(); ++i)
                if (nodes[i].live && indegree[i] > 0)
                    start = int(i);
            std::vector<int> path;
            std::map<int, std::size_t> seen;
            int cur = start;
            while (!seen.count(cur)) {
                seen[cur] = path.size();
                path.push_back(cur);
                for (int j : dependsOn[cur])
                    if (indegree[j] > 0) {
                        cur = j;
                        break;
                    }
            }
            std::vector<std::string> names;
            for (std::size_t k = seen[cur]; k < path.size(); ++k)
                names.push_back(nodes[path[k]].desc->name);
            names.push_back(nodes[cur].desc->name);
            std::reverse(names.begin(), names.end());
            diag.error(nodes[cur].desc->pointer,
                       fmt::format("the passes form a cycle: {}", fmt::join(names, " → ")));
        }
    }

    for (const auto& w : diag.warnings())
        plan.warnings.push_back(w);
    diag.throwIfErrors("");

    // --- steps, port demand, lifetimes, input demand
    // -----------------------------------------------
    std::map<int, int> stepOf;
    for (int i : order) {
        stepOf[i] = int(plan.steps.size());
        NodeState& n = nodes[i];
        PlanStep s;
        s.name = n.desc->name;
        s.type = n.desc->type;
        s.pointer = n.desc->pointer;
        s.pass = n.pass;
        s.io = n.io;
        s.params = n.params;
        s.inputs = n.inputs;
        plan.steps.push_back(std::move(s));
        plan.needsCamera |= n.io.needsCamera;
        plan.needsScene |= n.io.needsScene;
        plan.needsColorConfig |= n.io.needsColorConfig;
    }
    std::set<std::string> loaded;
    auto noteCaptureRead = [&](const SourceRef& ref, int step) {
        if (!ref.fromCapture || loaded.count(ref.buffer))
            return;
        loaded.insert(ref.buffer);
        plan.captureReads.push_back({ref.buffer, ref.channels, ref.kind});
        plan.loadsBefore[step].push_back(ref.buffer);
    };
    for (int s = 0; s < int(plan.steps.size()); ++s) {
        for (auto& [port, ref] : plan.steps[s].inputs) {
            if (!ref.fromCapture) {
                ref.step = stepOf.at(ref.step);
                plan.steps[ref.step].requestedOutputs.insert(ref.port);
            }
            noteCaptureRead(ref, s);
            plan.releaseAfter[ref.key] = std::max(plan.releaseAfter[ref.key], s);
        }
    }
    const int lastStep = int(plan.steps.size()) - 1;
    for (int o = 0; o < int(plan.outputs.size()); ++o) {
        int ready = -1;
        bool onlyCapture = true;
        for (const auto& src : plan.outputs[o].sources) {
            const SourceRef& ref = outputSources.at(src);  // ref.step is still a node index
            if (ref.fromCapture)
                continue;
            onlyCapture = false;
            const int step = stepOf.at(ref.step);
            plan.steps[step].requestedOutputs.insert(ref.port);
            ready = std::max(ready, step);
        }
        if (onlyCapture)
            ready = lastStep;
        plan.writesAfter[ready].push_back(o);
        for (const auto& src : plan.outputs[o].sources) {
            const SourceRef& ref = outputSources.at(src);
            plan.outputKinds[src] = ref.kind;
            noteCaptureRead(ref, std::max(ready, 0));
            auto it = plan.releaseAfter.find(ref.key);
            plan.releaseAfter[ref.key] =
                it == plan.releaseAfter.end() ? ready : std::max(it->second, ready);
        }
    }
    return plan;
}

std::size_t Plan::estimatePeakBytes(Extent frame) const {
    std::map<std::string, std::size_t> held;
    std::size_t current = 0, peak = 0;
    const std::size_t pixelBytes = sizeof(float) * std::size_t(frame.width) * frame.height;
    auto releaseAfterStep = [&](int s) {
        for (auto it = held.begin(); it != held.end();) {
            auto r = releaseAfter.find(it->first);
            if (r == releaseAfter.end() || r->second <= s) {
                current -= it->second;
                it = held.erase(it);
            } else {
                ++it;
            }
        }
    };
    for (int s = 0; s < int(steps.size()); ++s) {
        if (auto it = loadsBefore.find(s); it != loadsBefore.end())
            for (const auto& b : it->second)
                for (const auto& r : captureReads)
                    if (r.buffer == b) {
                        held["capture:" + b] = pixelBytes * r.channels;
                        current += pixelBytes * r.channels;
                    }
        for (const auto& o : steps[s].io.outputs) {
            if (!steps[s].requestedOutputs.count(o.name))
                continue;
            std::size_t bytes = 0;
            for (const Extent& e : steps[s].pass->outputExtents(o.name, frame))
                bytes += sizeof(float) * std::size_t(e.width) * e.height * o.channels.size();
            held[steps[s].name + "." + o.name] = bytes;
            current += bytes;
        }
        peak = std::max(peak, current);
        releaseAfterStep(s);
    }
    return peak;
}

nlohmann::json Plan::toJson(Extent frame) const {
    nlohmann::json j;
    j["steps"] = nlohmann::json::array();
    for (const auto& s : steps) {
        nlohmann::json step = {{"name", s.name}, {"type", s.type}, {"params", s.params}};
        step["inputs"] = nlohmann::json::object();
        for (const auto& [port, ref] : s.inputs)
            step["inputs"][port] = ref.key;
        step["outputs"] =
            std::vector<std::string>(s.requestedOutputs.begin(), s.requestedOutputs.end());
        step["needsScene"] = s.io.needsScene;
        j["steps"].push_back(step);
    }
    j["culled"] = nlohmann::json::array();
    for (const auto& c : culled)
        j["culled"].push_back({{"name", c.name}, {"type", c.type}, {"reason", c.reason}});
    j["captureReads"] = nlohmann::json::array();
    for (const auto& r : captureReads)
        j["captureReads"].push_back({{"buffer", r.buffer}, {"channels", r.channels}});
    j["outputs"] = nlohmann::json::array();
    for (const auto& o : outputs)
        j["outputs"].push_back({{"file", o.file}, {"sources", o.sources}, {"dump", o.isDump}});
    j["needsScene"] = needsScene;
    j["needsCamera"] = needsCamera;
    j["needsColorConfig"] = needsColorConfig;
    if (frame.width > 0) {
        j["frame"] = {{"width", frame.width}, {"height", frame.height}};
        j["peakBytes"] = estimatePeakBytes(frame);
    }
    j["warnings"] = nlohmann::json::array();
    for (const auto& w : warnings)
        j["warnings"].push_back({{"pointer", w.pointer}, {"message", w.message}});
    return j;
}

}  // namespace fp
