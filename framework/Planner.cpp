#include "framework/Planner.h"

#include "framework/ChainTemplate.h"
#include "foundation/Cuda.h"
#include "framework/CvarTable.h"
#include "foundation/Error.h"
#include "framework/SemanticBuffers.h"
#include "foundation/Suggest.h"

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
    std::map<std::string, std::string> pinned;  // PlanStep::pinned
    std::map<std::string, SourceRef> inputs;
    std::map<std::string, std::string> inputPointers;  // port → where its binding came from
    std::map<std::string, std::string> noPreviousCameraInputs;  // port → capture buffer
    /// Inputs rebound by "inputs"/--input PASS.INPUT=SOURCE: port → (source, where it was set).
    std::map<std::string, std::pair<std::string, std::string>> setInputs;
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

// The planner's state as it goes through its stages; each stage is one member function, run in
// the order makePlan lists them (Filament's FrameGraph: setup, cull, then execute).
class PlanBuilder {
public:
    PlanBuilder(const GraphDesc& graph, const PassRegistry& registry, const PlanInputs& in)
        : mWritten(graph), mRegistry(registry), mIn(in), mCvarTable(registry) {
        for (const auto& e : in.priorErrors)
            mDiag.error(e.pointer, e.message);
    }

    /// Light templates become plain passes, one copy per light of the scene.
    void expandTemplates() {
        mGraph = expandLightTemplates(mWritten, mIn.lightNames, mDiag, &mPlan.templates);
        mNodes.resize(mGraph.nodes.size());
        for (const auto& d : mGraph.nodes)
            mAllNames.push_back(d.name);
    }

    /// Every pass has a unique, addressable name and a known type.
    void validateNames() {
        for (std::size_t i = 0; i < mGraph.nodes.size(); ++i) {
            const NodeDesc& d = mGraph.nodes[i];
            mNodes[i].desc = &d;
            if (d.name.empty() || d.name.find_first_of(".:/ ") != std::string::npos)
                mDiag.error(d.pointer + "/name",
                            fmt::format("pass name '{}' must be non-empty without '.', ':', '/' "
                                        "or spaces",
                                        d.name));
            else if (!mNodeIndex.emplace(d.name, int(i)).second)
                mDiag.error(d.pointer + "/name",
                            fmt::format("pass name '{}' is used twice", d.name));
            mNodes[i].type = mRegistry.find(d.type);
            if (!mNodes[i].type)
                mDiag.error(d.pointer + "/type", fmt::format("unknown pass type '{}'{}", d.type,
                                                             didYouMean(d.type, mRegistry.ids())));
        }
    }

    /// Cvars of the config, then --cvar; unknown, unemulated and unused ones are warnings.
    void validateCvars() {
        for (const auto& [k, v] : mGraph.cvars.items())
            mCvars[mCvarTable.spelling(k)] = {v, "/cvars/" + jsonPointerEscape(k)};
        for (const auto& [k, v] : mIn.overrides.cvars.items())
            mCvars[mCvarTable.spelling(k)] = {v, fmt::format(fmt::runtime(mIn.overrides.cvarOrigin), k)};
        for (const auto& [name, cv] : mCvars) {
            const CvarMapping* m = mCvarTable.find(name);
            if (!m && mIn.allowUnknownCvars) {
                mDiag.warning(cv.where, fmt::format("unknown cvar '{}' is ignored{}", name,
                                                    didYouMean(name, mCvarTable.names())));
            } else if (!m) {
                // A typo would otherwise run the chain without the setting the user asked for.
                mDiag.error(cv.where, fmt::format("unknown cvar '{}'{} (--allow-unknown-cvars "
                                                  "ignores it with a warning)",
                                                  name, didYouMean(name, mCvarTable.names())));
            } else if (m->passType.empty() && cv.value == m->emulatedValue) {
                // The value the chain emulates: nothing to say.
            } else if (m->passType.empty()) {
                mDiag.warning(cv.where, fmt::format("cvar '{}' is not emulated by framepass ({})",
                                                    name, m->note));
            } else if (const auto types = mCvarTable.targets(name); std::none_of(
                           mGraph.nodes.begin(), mGraph.nodes.end(), [&](const NodeDesc& d) {
                               return std::find(types.begin(), types.end(), d.type) != types.end();
                           })) {
                mDiag.warning(cv.where, fmt::format("cvar '{}' sets {}.{}, but the chain has no "
                                                    "'{}' pass",
                                                    name, m->passType, m->param, m->passType));
            }
        }
    }

    /// Makes every pass from its parameters: defaults ← cvars ← config params ← --set.
    void instantiate() {
        const auto sets = setLayers();
        const auto inputs = inputLayers();
        for (std::size_t i = 0; i < mNodes.size(); ++i) {
            NodeState& n = mNodes[i];
            if (!n.type)
                continue;
            const std::string paramsPtr = n.desc->pointer + "/params";
            const std::size_t errorsBefore = mDiag.errors().size();
            nlohmann::json merged = nlohmann::json::object();
            for (const auto& [name, cv] : mCvars) {
                const CvarMapping* m = mCvarTable.find(name, n.desc->type);
                if (!m)
                    continue;
                nlohmann::json layer = {{m->param, cv.value}};
                validateLayer(*n.type, layer, paramsPtr, cv.where,
                              fmt::format("cvar {} sets {}.{}", name, n.desc->name, m->param),
                              mDiag);
                merged[m->param] = cv.value;
                // The config's params and --set come later and win: a cvar they shadow does
                // nothing, which a user sweeping it (bench, tune) must hear.
                const auto set = sets.find(int(i));
                const bool byParams = n.desc->params.is_object() && n.desc->params.contains(m->param);
                if (byParams || (set != sets.end() && set->second.values.contains(m->param)))
                    mDiag.warning(cv.where,
                                  fmt::format("cvar {} sets {}.{}, but {} sets it too and wins: "
                                              "the cvar has no effect on '{}'",
                                              name, n.desc->name, m->param,
                                              byParams ? paramsPtr + "/" + m->param
                                                       : set->second.where.at(m->param),
                                              n.desc->name));
            }
            validateLayer(*n.type, n.desc->params, paramsPtr, "", "", mDiag);
            if (n.desc->params.is_object())
                for (const auto& [k, v] : n.desc->params.items()) {
                    merged[k] = v;
                    n.pinned[k] = paramsPtr + "/" + k;
                }
            std::vector<std::string> notParams;  // set names that are no parameter of the type
            if (auto it = sets.find(int(i)); it != sets.end()) {
                // Each value on its own, so that an error names the setting that made it.
                for (const auto& [k, v] : it->second.values.items()) {
                    const std::string name = k;  // a lambda may not capture a structured binding
                    if (std::none_of(n.type->params.begin(), n.type->params.end(),
                                     [&](const ParamInfo& p) { return p.name == name; }))
                        notParams.push_back(name);
                    else {
                        validateLayer(*n.type, nlohmann::json::object({{k, v}}), paramsPtr,
                                      it->second.where.at(k), "", mDiag);
                        merged[k] = v;
                        n.pinned[k] = it->second.where.at(k);
                    }
                }
            }
            // Every layer was validated above. With errors, the pass is still made from its
            // defaults so that its ports can be checked too: all problems come out in one round.
            Diagnostics ignored;
            const bool paramsOk = mDiag.errors().size() == errorsBefore;
            n.pass = n.type->create(paramsOk ? merged : nlohmann::json::object(), paramsPtr,
                                    ignored, n.params);
            n.io = n.pass->describe();
            for (const auto& name : notParams) {
                const SetLayer& layer = sets.at(int(i));
                const std::string& where = layer.where.at(name);
                if (findPort(n.io.inputs, name))  // a parameter and an input are set apart
                    mDiag.error(where, fmt::format("'{}' is an input of pass '{}', not a "
                                                   "parameter: rebind it with {}",
                                                   name, n.desc->name,
                                                   inputSpelling(where, n.desc->name + "." + name)));
                else  // the parameter check says what is wrong, with its did-you-mean
                    validateLayer(*n.type, nlohmann::json::object({{name, layer.values.at(name)}}),
                                  paramsPtr, where, "", mDiag);
            }
            if (auto it = inputs.find(int(i)); it != inputs.end())
                for (const auto& [port, set] : it->second) {
                    if (findPort(n.io.inputs, port))
                        n.setInputs[port] = set;
                    else
                        mDiag.error(set.second, fmt::format("pass '{}' ({}) has no input '{}'{}",
                                                            n.desc->name, n.desc->type, port,
                                                            didYouMean(port, portNames(n.io.inputs))));
                }
        }
    }

    /// Binds every input port to the source the config names, else to its capture default.
    void bindInputs() {
        mDependsOn.resize(mNodes.size());
        mUnboundRequired.resize(mNodes.size());
        for (std::size_t i = 0; i < mNodes.size(); ++i) {
            NodeState& n = mNodes[i];
            if (!n.pass)
                continue;
            for (const auto& [port, src] : n.desc->inputs)
                if (!findPort(n.io.inputs, port))
                    mDiag.error(
                        n.desc->pointer + "/inputs/" + jsonPointerEscape(port),
                        fmt::format("pass '{}' ({}) has no input '{}'{}", n.desc->name,
                                    n.desc->type, port, didYouMean(port, portNames(n.io.inputs))));
            for (const auto& port : n.io.inputs) {
                std::string text, where;
                if (auto set = n.setInputs.find(port.name); set != n.setInputs.end()) {
                    text = set->second.first;
                    where = set->second.second;
                } else if (auto it = n.desc->inputs.find(port.name); it != n.desc->inputs.end()) {
                    text = it->second;
                    where = n.desc->pointer + "/inputs/" + jsonPointerEscape(port.name);
                } else {
                    text = port.captureDefault.empty() ? "" : "capture:" + port.captureDefault;
                    where = n.desc->pointer;
                    // An optional input whose default buffer this capture lacks stays unbound
                    // (a Blender capture has no InstanceId): the pass runs without it.
                    if (port.optional && mIn.availableBuffers &&
                        !mIn.availableBuffers->count(port.captureDefault))
                        text.clear();
                }
                if (text.empty()) {
                    if (!port.optional)
                        mUnboundRequired[i].push_back(port.name);
                    else if (const std::string& b = port.captureWhenNoPreviousCamera;
                             !b.empty() && mIn.availableBuffers && mIn.availableBuffers->count(b))
                        n.noPreviousCameraInputs[port.name] = b;
                    continue;
                }
                SourceRef ref;
                if (!resolveSource(text, where, int(port.channels.size()), ref))
                    continue;
                if (!ref.fromCapture)
                    mDependsOn[i].insert(ref.step);
                n.inputs[port.name] = ref;
                n.inputPointers[port.name] = where;
            }
        }
    }

    /// The files to write (and --dump intermediates) are the roots of the graph.
    void bindOutputs() {
        mPlan.outputs = mGraph.outputs;
        std::vector<std::string> dumps = mIn.overrides.dumps;
        if (std::find(dumps.begin(), dumps.end(), "all") != dumps.end()) {
            dumps.erase(std::remove(dumps.begin(), dumps.end(), "all"), dumps.end());
            for (const auto& n : mNodes)
                if (n.pass)
                    for (const auto& o : n.io.outputs)
                        dumps.push_back(n.desc->name + "." + o.name);
        }
        for (const auto& d : dumps)
            mPlan.outputs.push_back({d + ".exr", {d}, fmt::format(fmt::runtime(mIn.overrides.dumpOrigin), d), true});
        for (const auto& out : mPlan.outputs)
            for (std::size_t k = 0; k < out.sources.size(); ++k) {
                SourceRef ref;
                const std::string where = !out.isDump && out.sources.size() > 1
                                              ? fmt::format("{}/{}", out.pointer, k)
                                              : out.pointer;
                if (!resolveSource(out.sources[k], where, 0, ref))
                    continue;
                if (!ref.fromCapture)
                    mRoots.insert(ref.step);
                mOutputSources[ref.key] = ref;
            }
    }

    /// Reverse reachability from the roots (Falcor resolveExecutionOrder): the rest is culled.
    void cull() {
        if (mIn.overrides.runEveryPass)
            for (std::size_t i = 0; i < mNodes.size(); ++i)
                if (mNodes[i].pass)
                    mRoots.insert(int(i));
        std::vector<int> stack(mRoots.begin(), mRoots.end());
        while (!stack.empty()) {
            const int i = stack.back();
            stack.pop_back();
            if (mNodes[i].live)
                continue;
            mNodes[i].live = true;
            for (int j : mDependsOn[i])
                stack.push_back(j);
        }
        for (const auto& n : mNodes)
            if (!n.live && n.pass)
                mPlan.culled.push_back({n.desc->name, n.desc->type,
                                        mRoots.empty() ? "no outputs are requested"
                                                       : "no requested output depends on it"});
    }

    /// Checks only live passes need: required inputs bound, capture buffers present.
    void validateLive() {
        for (std::size_t i = 0; i < mNodes.size(); ++i) {
            const NodeState& n = mNodes[i];
            if (!n.live)
                continue;
            for (const auto& port : mUnboundRequired[i])
                mDiag.error(n.desc->pointer + "/inputs",
                            fmt::format("required input '{}' of pass '{}' ({}) is not bound", port,
                                        n.desc->name, n.desc->type));
        }
        for (const auto& n : mNodes)
            if (n.live)
                for (const auto& [port, ref] : n.inputs)
                    checkAvailable(ref, n.inputPointers.at(port));
        for (const auto& out : mPlan.outputs)
            for (const auto& s : out.sources)
                if (auto it = mOutputSources.find(s); it != mOutputSources.end())
                    checkAvailable(it->second, out.pointer);
    }

    /// Kahn's algorithm, ties broken by declaration order; a cycle is reported with its path.
    void order() {
        std::vector<int> indegree(mNodes.size(), 0);
        std::vector<std::vector<int>> users(mNodes.size());
        for (std::size_t i = 0; i < mNodes.size(); ++i)
            if (mNodes[i].live)
                for (int j : mDependsOn[i]) {
                    ++indegree[i];
                    users[j].push_back(int(i));
                }
        std::priority_queue<int, std::vector<int>, std::greater<int>> ready;
        for (std::size_t i = 0; i < mNodes.size(); ++i)
            if (mNodes[i].live && indegree[i] == 0)
                ready.push(int(i));
        while (!ready.empty()) {
            const int i = ready.top();
            ready.pop();
            mOrder.push_back(i);
            for (int u : users[i])
                if (--indegree[u] == 0)
                    ready.push(u);
        }
        const std::size_t liveCount =
            std::count_if(mNodes.begin(), mNodes.end(), [](const NodeState& n) { return n.live; });
        if (mOrder.size() != liveCount)
            reportCycle(indegree);
    }

    /// Throws every error found so far; keeps the warnings for the plan.
    void finishValidation() {
        for (const auto& w : mDiag.warnings())
            mPlan.warnings.push_back(w);
        mDiag.throwIfErrors("");
    }

    /// The live passes as steps in execution order, with what each needs of the session.
    void makeSteps() {
        for (int i : mOrder) {
            mStepOf[i] = int(mPlan.steps.size());
            NodeState& n = mNodes[i];
            PlanStep s;
            s.name = n.desc->name;
            s.type = n.desc->type;
            s.pointer = n.desc->pointer;
            s.pass = n.pass;
            s.io = n.io;
            s.params = n.params;
            s.pinned = n.pinned;
            s.inputs = n.inputs;
            s.noPreviousCameraInputs = n.noPreviousCameraInputs;
            mPlan.steps.push_back(std::move(s));
            mPlan.needsCamera |= n.io.needsCamera;
            mPlan.needsScene |= n.io.needsScene;
            mPlan.needsLights |= n.io.needsLights || n.io.needsScene;
            mPlan.needsColorConfig |= n.io.needsColorConfig;
        }
    }

    /// Where each step runs: with --device cuda (or "device": "cuda"), every pass with a CUDA
    /// kernel goes to the GPU and the rest stay on the CPU (docs/gpu.md).
    void placeSteps() {
        const std::string& device =
            mIn.overrides.device.empty() ? mGraph.device : mIn.overrides.device;
        if (device == "cpu")
            return;
        if (device != "cuda")
            throw UsageError(fmt::format("unknown device '{}'; known: cpu, cuda", device));
        if (!cuda::built())
            throw UsageError(fmt::format("--device cuda: {}", cuda::unavailableReason()));
        mPlan.device = Device::Cuda;
        for (PlanStep& s : mPlan.steps)
            if (s.pass->hasCudaKernel())
                s.device = Device::Cuda;
    }

    /// Which outputs each step must produce, when each image can be freed, and which capture
    /// buffers are read (and before which step).
    void computeLifetimes() {
        for (int s = 0; s < int(mPlan.steps.size()); ++s) {
            for (auto& [port, ref] : mPlan.steps[s].inputs) {
                if (!ref.fromCapture) {
                    ref.step = mStepOf.at(ref.step);
                    mPlan.steps[ref.step].requestedOutputs.insert(ref.port);
                }
                noteCaptureRead(ref, s);
                mPlan.releaseAfter[ref.key] = std::max(mPlan.releaseAfter[ref.key], s);
            }
        }
        const int lastStep = int(mPlan.steps.size()) - 1;
        for (int o = 0; o < int(mPlan.outputs.size()); ++o) {
            int ready = -1;
            bool onlyCapture = true;
            for (const auto& src : mPlan.outputs[o].sources) {
                const SourceRef& ref = mOutputSources.at(src);  // ref.step is still a node index
                if (ref.fromCapture)
                    continue;
                onlyCapture = false;
                const int step = mStepOf.at(ref.step);
                mPlan.steps[step].requestedOutputs.insert(ref.port);
                ready = std::max(ready, step);
            }
            if (onlyCapture)
                ready = lastStep;
            // dumpsOnly: a config output is made as the config asks, but not handed over.
            if (!mIn.overrides.dumpsOnly || mPlan.outputs[o].isDump)
                mPlan.writesAfter[ready].push_back(o);
            for (const auto& src : mPlan.outputs[o].sources) {
                const SourceRef& ref = mOutputSources.at(src);
                mPlan.outputKinds[src] = ref.kind;
                noteCaptureRead(ref, std::max(ready, 0));
                auto it = mPlan.releaseAfter.find(ref.key);
                mPlan.releaseAfter[ref.key] =
                    it == mPlan.releaseAfter.end() ? ready : std::max(it->second, ready);
            }
        }
    }

    Plan take() { return std::move(mPlan); }

private:
    struct CvarValue {
        nlohmann::json value;
        std::string where;  // the place the user typed it
    };
    struct SetLayer {
        nlohmann::json values = nlohmann::json::object();
        std::map<std::string, std::string> where;  // parameter → what set it ("--set p.x")
    };

    // Each PASS.NAME → value of the config's map `config` (pointers under `prefix`) and then of
    // a door's `overrides` (named by the fmt pattern `origin`), in that order, handed to `use`
    // with the step it names; a value `accepts` refuses, a target without a dot (`expected`
    // says what is) or naming no pass is an error.
    template <class Overrides, class Accepts, class Use>
    void forEachTarget(const nlohmann::json& config, const std::string& prefix,
                       const Overrides& overrides, const std::string& origin,
                       const char* expected, const Accepts& accepts, const Use& use) {
        std::vector<std::tuple<std::string, nlohmann::json, std::string>> targets;
        for (const auto& [target, value] : config.items())
            targets.emplace_back(target, value, prefix + jsonPointerEscape(target));
        for (const auto& [target, value] : overrides)
            targets.emplace_back(target, value, fmt::format(fmt::runtime(origin), target));
        for (const auto& [target, value, where] : targets) {
            const auto dot = target.find('.');
            if (dot == std::string::npos || !accepts(value)) {
                mDiag.error(where, expected);
                continue;
            }
            const std::string pass = target.substr(0, dot);
            auto it = mNodeIndex.find(pass);
            if (it == mNodeIndex.end()) {
                mDiag.error(where,
                            fmt::format("no pass named '{}'{}", pass, didYouMean(pass, mAllNames)));
                continue;
            }
            use(it->second, target.substr(dot + 1), value, where);
        }
    }

    // The config's "set" and then --set PASS.PARAM=VALUE, grouped per pass (a later value of a
    // parameter replaces an earlier one).
    std::map<int, SetLayer> setLayers() {
        std::map<int, SetLayer> layers;
        forEachTarget(mGraph.sets, "/set/", mIn.overrides.sets, mIn.overrides.setOrigin,
                      "expected PASS.PARAM=VALUE", [](const nlohmann::json&) { return true; },
                      [&](int step, const std::string& param, const nlohmann::json& value,
                          const std::string& where) {
                          layers[step].values[param] = value;
                          layers[step].where[param] = where;
                      });
        return layers;
    }

    // The config's "inputs" and then --input PASS.INPUT=SOURCE, grouped per pass: port →
    // (source, where it was set); a later one of a port replaces an earlier one.
    std::map<int, std::map<std::string, std::pair<std::string, std::string>>> inputLayers() {
        std::map<int, std::map<std::string, std::pair<std::string, std::string>>> layers;
        forEachTarget(mGraph.inputs, "/inputs/", mIn.overrides.inputs, mIn.overrides.inputOrigin,
                      "expected PASS.INPUT and a source's name (\"pass.port\" or \"capture:Buffer\")",
                      [](const nlohmann::json& v) { return v.is_string(); },
                      [&](int step, const std::string& port, const nlohmann::json& source,
                          const std::string& where) {
                          layers[step][port] = {source.get<std::string>(), where};
                      });
        return layers;
    }

    // How the door that set `where` rebinds input `target` instead: the config's "inputs" for
    // the config's "set", else the door's own spelling (--input, set_input(), /inputs/).
    std::string inputSpelling(const std::string& where, const std::string& target) const {
        if (where.rfind("/set/", 0) == 0)
            return fmt::format("\"inputs\": {{\"{}\": …}}", target);
        return fmt::format(fmt::runtime(mIn.overrides.inputOrigin), target);
    }

    // Returns false (with an error) when `text` does not name an existing source.
    bool resolveSource(const std::string& text,
                       const std::string& where,
                       int wantChannels,
                       SourceRef& ref) {
        ref = {};
        ref.key = text;
        const bool ok = text.rfind("capture:", 0) == 0
                            ? resolveCapture(text.substr(8), where, wantChannels, ref)
                            : resolvePassOutput(text, where, ref);
        if (!ok)
            return false;
        if (wantChannels > 0 && ref.channels != wantChannels) {
            mDiag.error(where,
                        fmt::format("'{}' has {} channel{}, the input needs {}", text, ref.channels,
                                    ref.channels == 1 ? "" : "s", wantChannels));
            return false;
        }
        return true;
    }

    bool resolveCapture(const std::string& buffer,
                        const std::string& where,
                        int wantChannels,
                        SourceRef& ref) {
        ref.fromCapture = true;
        ref.buffer = buffer;
        if (const SemanticBuffer* b = findSemanticBuffer(buffer)) {
            ref.kind = b->kind;
            ref.channels = int(b->channels.size());
        } else if (isTruthBuffer(buffer)) {
            // Truth layers are data: a reference is compared as stored, never converted.
            ref.kind = PortKind::Data;
            auto known = mIn.truthChannels.find(buffer);
            ref.channels = known != mIn.truthChannels.end() ? known->second
                                                            : (wantChannels > 0 ? wantChannels : 3);
        } else {
            mDiag.error(where, fmt::format("unknown capture buffer '{}'{}", buffer,
                                           didYouMean(buffer, captureBufferNames())));
            return false;
        }
        return true;
    }

    bool resolvePassOutput(const std::string& text, const std::string& where, SourceRef& ref) {
        const auto dot = text.find('.');
        if (dot == std::string::npos) {
            mDiag.error(where, fmt::format("'{}' should be 'capture:Buffer' or 'pass.port'", text));
            return false;
        }
        const std::string pass = text.substr(0, dot);
        ref.port = text.substr(dot + 1);
        auto it = mNodeIndex.find(pass);
        if (it == mNodeIndex.end()) {
            mDiag.error(where,
                        fmt::format("no pass named '{}'{}", pass, didYouMean(pass, mAllNames)));
            return false;
        }
        ref.step = it->second;  // node index for now; remapped to step index by computeLifetimes
        const NodeState& producer = mNodes[it->second];
        if (!producer.pass)
            return false;  // its own errors are already reported
        const PortSpec* out = findPort(producer.io.outputs, ref.port);
        if (!out) {
            mDiag.error(
                where, fmt::format("pass '{}' ({}) has no output '{}'{}", pass, producer.desc->type,
                                   ref.port, didYouMean(ref.port, portNames(producer.io.outputs))));
            return false;
        }
        ref.kind = out->kind;
        ref.channels = int(out->channels.size());
        return true;
    }

    void checkAvailable(const SourceRef& ref, const std::string& where) {
        if (!ref.fromCapture || !mIn.availableBuffers)
            return;
        if (mIn.availableBuffers->count(ref.buffer))
            return;
        std::vector<std::string> have(mIn.availableBuffers->begin(), mIn.availableBuffers->end());
        mDiag.error(where, fmt::format("the capture has no '{}' buffer{}; it has [{}]", ref.buffer,
                                       didYouMean(ref.buffer, have), fmt::join(have, ", ")));
    }

    // Walks dependencies from a node left over until one repeats: that loop is the cycle.
    void reportCycle(const std::vector<int>& indegree) {
        int start = -1;
        for (std::size_t i = 0; i < mNodes.size(); ++i)
            if (mNodes[i].live && indegree[i] > 0)
                start = int(i);
        std::vector<int> path;
        std::map<int, std::size_t> seen;
        int cur = start;
        while (!seen.count(cur)) {
            seen[cur] = path.size();
            path.push_back(cur);
            for (int j : mDependsOn[cur])
                if (indegree[j] > 0) {
                    cur = j;
                    break;
                }
        }
        std::vector<std::string> names;
        for (std::size_t k = seen[cur]; k < path.size(); ++k)
            names.push_back(mNodes[path[k]].desc->name);
        names.push_back(mNodes[cur].desc->name);
        std::reverse(names.begin(), names.end());
        mDiag.error(mNodes[cur].desc->pointer,
                    fmt::format("the passes form a cycle: {}", fmt::join(names, " → ")));
    }

    void noteCaptureRead(const SourceRef& ref, int step) {
        if (!ref.fromCapture || mLoaded.count(ref.buffer))
            return;
        mLoaded.insert(ref.buffer);
        mPlan.captureReads.push_back({ref.buffer, ref.channels, ref.kind});
        mPlan.loadsBefore[step].push_back(ref.buffer);
    }

    const GraphDesc& mWritten;
    const PassRegistry& mRegistry;
    const PlanInputs& mIn;
    const CvarTable mCvarTable;
    Diagnostics mDiag;
    Plan mPlan;
    GraphDesc mGraph;  // the chain with its templates expanded
    std::vector<NodeState> mNodes;
    std::map<std::string, int> mNodeIndex;
    std::vector<std::string> mAllNames;
    std::map<std::string, CvarValue> mCvars;
    std::vector<std::set<int>> mDependsOn;
    std::vector<std::vector<std::string>> mUnboundRequired;
    std::set<int> mRoots;
    std::map<std::string, SourceRef> mOutputSources;
    std::vector<int> mOrder;
    std::map<int, int> mStepOf;
    std::set<std::string> mLoaded;
};

}  // namespace

Plan makePlan(const GraphDesc& graph, const PassRegistry& registry, const PlanInputs& in) {
    PlanBuilder b(graph, registry, in);
    b.expandTemplates();
    b.validateNames();
    b.validateCvars();
    b.instantiate();
    b.bindInputs();
    b.bindOutputs();
    b.cull();
    b.validateLive();
    b.order();
    b.finishValidation();
    b.makeSteps();
    b.placeSteps();
    b.computeLifetimes();
    return b.take();
}

Plan::MemoryEstimate Plan::estimateMemory(Extent frame, bool preread, bool sequence) const {
    std::map<std::string, std::size_t> held;
    std::size_t current = 0;
    MemoryEstimate best;
    // Every history from the start in a sequence (a step's new state replaces its old one after
    // it; during it the new one is in its scratch); on a first frame, those kept so far.
    std::size_t history = 0;
    if (sequence)
        for (const PlanStep& step : steps)
            history += step.pass->memoryBytes(frame).history;
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
        for (const auto& [step, buffers] : loadsBefore) {
            if (preread ? s != 0 : step != s)
                continue;
            for (const auto& b : buffers)
                for (const auto& r : captureReads)
                    if (r.buffer == b) {
                        const std::size_t bytes = imageBytes(frame, r.channels);
                        held["capture:" + b] = bytes;
                        current += bytes;
                    }
        }
        // An output nobody reads may still be written by the pass: it lives while the step runs.
        const PassMemory own = steps[s].pass->memoryBytes(frame);
        std::size_t transient = own.scratch;
        for (const auto& o : steps[s].io.outputs) {
            const std::size_t bytes =
                imageBytes(steps[s].pass->outputExtents(o.name, frame), int(o.channels.size()));
            if (!steps[s].requestedOutputs.count(o.name)) {
                transient += bytes;
                continue;
            }
            held[steps[s].name + "." + o.name] = bytes;
            current += bytes;
        }
        if (current + transient + history >= best.peak())
            best = {current, transient, history, steps[s].name};
        if (!sequence)
            history += own.history;
        releaseAfterStep(s);
    }
    return best;
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
        step["device"] = s.device == Device::Cuda ? "cuda" : "cpu";
        if (!s.pinned.empty()) step["pinned"] = s.pinned;
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
    j["templates"] = nlohmann::json::array();
    for (const auto& t : templates)
        j["templates"].push_back(
            {{"pointer", t.pointer}, {"lights", t.lights}, {"passes", t.passes}});
    j["device"] = device == Device::Cuda ? "cuda" : "cpu";
    j["needsScene"] = needsScene;
    j["needsLights"] = needsLights;
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
