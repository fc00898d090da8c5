#include "framework/CvarTable.h"
#include "foundation/Error.h"
#include "framework/Executor.h"
#include "framework/Planner.h"
#include "framework/SemanticBuffers.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <set>

using namespace fp;

namespace {

struct FakeParams {
    int quality = 1;  //!< [0, 4]
    float radius = 1.0f;
    bool flag = false;
};

std::set<std::string>& executed() {
    static std::set<std::string> s;
    return s;
}

// Fake passes with fixed ports; `execute` records that it ran and writes constant outputs.
template <class Ports>
class FakePass final : public Pass {
public:
    using Params = FakeParams;
    static ParamSpec<Params> paramSpec() {
        ParamSpec<Params> s;
        s.add("quality", &Params::quality, "quality level").range(0, 4).cvar("r.Fake.Quality");
        s.add("radius", &Params::radius, "radius").range(0.0, 100.0);
        s.add("flag", &Params::flag, "a flag");
        return s;
    }
    explicit FakePass(const Params& p) : mParams(p) {}
    PassIO describe() const override { return Ports::describe(); }
    // `quality` one-channel planes of scratch; `flag`: a two-channel history.
    PassMemory memoryBytes(Extent frame) const override {
        return {std::size_t(mParams.quality) * imageBytes(frame, 1),
                mParams.flag ? imageBytes(frame, 2) : 0};
    }
    void execute(PassContext& ctx) override {
        executed().insert(Ports::kId);
        for (const auto& o : describe().outputs)
            if (ctx.isRequested(o.name))
                ctx.output(o.name, {ctx.frame().extent});
    }
    Params mParams;
};

struct DepthReader {  // reads SceneDepth by default
    static constexpr const char* kId = "depth_reader";
    static PassIO describe() {
        PassIO io;
        io.inputs = {{.name = "depth", .channels = {"Z"}, .captureDefault = "SceneDepth"}};
        io.outputs = {{.name = "out", .channels = {"Y"}}};
        return io;
    }
};
struct ColorReader {  // reads SceneColor and, optionally, anything one-channel
    static constexpr const char* kId = "color_reader";
    static PassIO describe() {
        PassIO io;
        io.inputs = {{.name = "color",
                      .channels = {"R", "G", "B"},
                      .kind = PortKind::Color,
                      .captureDefault = "SceneColor"},
                     {.name = "extra", .channels = {"Y"}, .optional = true}};
        io.outputs = {{.name = "out", .channels = {"Y"}}};
        return io;
    }
};
struct AoReader {  // reads GBufferAO when the capture has it
    static constexpr const char* kId = "ao_reader";
    static PassIO describe() {
        PassIO io;
        io.inputs = {{.name = "ao", .channels = {"Y"}, .optional = true,
                      .captureDefault = "GBufferAO"}};
        io.outputs = {{.name = "out", .channels = {"Y"}}};
        return io;
    }
};
struct Relay {  // needs an explicit input; traces rays
    static constexpr const char* kId = "relay";
    static PassIO describe() {
        PassIO io;
        io.inputs = {{.name = "in", .channels = {"Y"}}};
        io.outputs = {{.name = "out", .channels = {"Y"}}};
        io.needsScene = true;
        return io;
    }
};

PassRegistry fakeRegistry() {
    PassRegistry r;
    r.add<FakePass<DepthReader>>("depth_reader", "");
    r.add<FakePass<ColorReader>>("color_reader", "");
    r.add<FakePass<Relay>>("relay", "");
    r.add<FakePass<AoReader>>("ao_reader", "");
    r.recognise("r.Fake.Unemulated", 1, "recognised, runs as 1");
    return r;
}

NodeDesc node(std::string name,
              std::string type,
              std::map<std::string, std::string> inputs = {},
              nlohmann::json params = nlohmann::json::object()) {
    static int counter = 0;
    return {name, type, params, inputs, "/passes/" + std::to_string(counter++ % 100)};
}

GraphDesc graph(std::vector<NodeDesc> nodes, std::vector<std::string> outputs) {
    GraphDesc g;
    for (std::size_t i = 0; i < nodes.size(); ++i)
        nodes[i].pointer = "/passes/" + std::to_string(i);
    g.nodes = nodes;
    for (const auto& o : outputs)
        g.outputs.push_back({o + ".exr", {o}, "/outputs/" + o, false});
    return g;
}

std::string planError(const GraphDesc& g, const PlanInputs& in = {}) {
    try {
        makePlan(g, fakeRegistry(), in);
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_SUITE("planner") {
    TEST_CASE("the memory estimate adds the running step's scratch and the histories kept") {
        // a reads SceneDepth (1 channel) into a.out; c reads a.out into c.out, the file. a has 2
        // planes of scratch and a 2-channel history. P = one plane of 100×10, rows padded to 112.
        const Extent e{100, 10};
        const std::size_t P = 112 * 10 * sizeof(float);
        CHECK(imageBytes(e, 1) == P);
        const auto g = graph({node("a", "depth_reader", {}, {{"quality", 2}, {"flag", true}}),
                              node("c", "relay", {{"in", "a.out"}}, {{"quality", 0}})},
                             {"c.out"});
        const Plan plan = makePlan(g, fakeRegistry(), {});
        REQUIRE(plan.steps.size() == 2);
        // First frame. During a: the depth, a.out and a's scratch (4P). During c: a.out, c.out
        // and the history a kept (4P); no history yet during a.
        const Plan::MemoryEstimate first = plan.estimateMemory(e);
        CHECK(first.peak() == 4 * P);
        // Later frames start with a's history: during a, 2P more (6P), the peak.
        const Plan::MemoryEstimate later = plan.estimateMemory(e, false, true);
        CHECK(later.peak() == 6 * P);
        CHECK(later.peakStep == "a");
        CHECK(later.scratch == 2 * P);
        CHECK(later.history == 2 * P);
        CHECK(later.images == 2 * P);
        CHECK(plan.estimatePeakBytes(e) == first.peak());
    }

    TEST_CASE("passes with no path to a requested output are culled and never run") {
        const auto g = graph({node("a", "depth_reader"), node("b", "color_reader"),
                              node("c", "relay", {{"in", "a.out"}})},
                             {"b.out"});
        const Plan plan = makePlan(g, fakeRegistry(), {});
        REQUIRE(plan.steps.size() == 1);
        CHECK(plan.steps[0].name == "b");
        REQUIRE(plan.culled.size() == 2);
        CHECK(plan.culled[0].name == "a");
        CHECK(plan.culled[1].name == "c");
        CHECK(plan.culled[0].reason == "no requested output depends on it");
        // Channel demand: only what live passes read — SceneColor, not SceneDepth.
        REQUIRE(plan.captureReads.size() == 1);
        CHECK(plan.captureReads[0].buffer == "SceneColor");
        // Geometry is needed only by 'relay', which was culled.
        CHECK_FALSE(plan.needsScene);

        executed().clear();
        test::MemorySource src;
        src.info.extent = {4, 4};
        src.buffers["SceneColor"] = Image(4, 4, {"R", "G", "B"});
        test::MemorySink sink;
        executePlan(plan, src, sink);
        CHECK(executed() == std::set<std::string>{"color_reader"});
        CHECK(src.loaded == std::vector<std::string>{"SceneColor"});
        CHECK(sink.layers.count("b.out") == 1);
    }

    TEST_CASE("a dump keeps its producer alive, and the scene is then needed") {
        const auto g =
            graph({node("a", "depth_reader"), node("c", "relay", {{"in", "a.out"}})}, {});
        PlanInputs in;
        in.overrides.dumps = {"c.out"};
        const Plan plan = makePlan(g, fakeRegistry(), in);
        REQUIRE(plan.steps.size() == 2);
        CHECK(plan.steps[0].name == "a");
        CHECK(plan.steps[1].name == "c");
        CHECK(plan.needsScene);
        CHECK(plan.outputs.back().isDump);
    }

    TEST_CASE("runEveryPass culls nothing; dumpsOnly makes the config's outputs but hands over only the dumps") {
        const auto g = graph({node("a", "depth_reader"), node("b", "color_reader"),
                              node("c", "color_reader")},
                             {"b.out"});
        PlanInputs in;
        in.overrides.runEveryPass = true;
        in.overrides.dumpsOnly = true;
        in.overrides.dumps = {"c.out"};
        const Plan plan = makePlan(g, fakeRegistry(), in);
        CHECK(plan.steps.size() == 3);
        CHECK(plan.culled.empty());
        executed().clear();
        test::MemorySource src;
        src.info.extent = {4, 4};
        src.buffers["SceneColor"] = Image(4, 4, {"R", "G", "B"});
        src.buffers["SceneDepth"] = Image(4, 4, {"Z"});
        test::MemorySink sink;
        executePlan(plan, src, sink);
        CHECK(executed() == std::set<std::string>{"depth_reader", "color_reader"});
        CHECK(sink.layers.count("c.out") == 1);
        CHECK(sink.layers.count("b.out") == 0);  // made (requested) but not handed over
        CHECK(plan.steps[1].requestedOutputs.count("out") == 1);
    }

    TEST_CASE("a step cache reads and uploads no capture buffer twice for one frame, and keeps what a step made") {
        const auto g = graph({node("a", "depth_reader"), node("b", "color_reader")}, {});
        PlanInputs one, both;
        one.overrides.dumps = {"a.out"};
        both.overrides.dumps = {"a.out", "b.out"};
        const Plan planOne = makePlan(g, fakeRegistry(), one);
        const Plan planBoth = makePlan(g, fakeRegistry(), both);
        test::MemorySource src;
        src.info.extent = {4, 4};
        src.buffers["SceneColor"] = Image(4, 4, {"R", "G", "B"});
        src.buffers["SceneDepth"] = Image(4, 4, {"Z"});
        StepCache cache;
        cache.sourceId = "memory";
        test::MemorySink sink;
        executePlan(planOne, src, sink, {}, nullptr, &cache);
        CHECK(src.loaded == std::vector<std::string>{"SceneDepth"});
        // One more output asked for: only its step runs, and only its buffer is read.
        executed().clear();
        FrameReport r = executePlan(planBoth, src, sink, {}, nullptr, &cache);
        CHECK(executed() == std::set<std::string>{"color_reader"});
        CHECK(r.reusedSteps == 1);
        CHECK(src.loaded == std::vector<std::string>{"SceneDepth", "SceneColor"});
        // Again, and with fewer outputs: nothing runs, nothing is read.
        executed().clear();
        r = executePlan(planBoth, src, sink, {}, nullptr, &cache);
        CHECK(r.executedSteps == 0);
        r = executePlan(planOne, src, sink, {}, nullptr, &cache);
        CHECK(r.executedSteps == 0);
        CHECK(executed().empty());
        CHECK(src.loaded.size() == 2);
        // Another frame of the source: its buffers are read afresh.
        src.info.number = 2;
        executePlan(planOne, src, sink, {}, nullptr, &cache);
        CHECK(src.loaded == std::vector<std::string>{"SceneDepth", "SceneColor", "SceneDepth"});
    }

    TEST_CASE("declaration order breaks ties in the topological order") {
        const auto g = graph({node("z", "color_reader"), node("y", "depth_reader"),
                              node("x", "relay", {{"in", "y.out"}})},
                             {"x.out", "z.out"});
        const Plan plan = makePlan(g, fakeRegistry(), {});
        REQUIRE(plan.steps.size() == 3);
        CHECK(plan.steps[0].name == "z");
        CHECK(plan.steps[1].name == "y");
        CHECK(plan.steps[2].name == "x");
        // y.out is read by x only: released right after x (step 2).
        CHECK(plan.releaseAfter.at("y.out") == 2);
    }

    TEST_CASE("a cycle is reported with its path") {
        const auto g =
            graph({node("p", "relay", {{"in", "q.out"}}), node("q", "relay", {{"in", "p.out"}})},
                  {"p.out"});
        const std::string err = planError(g);
        CHECK(err.find("the passes form a cycle: ") != std::string::npos);
        CHECK((err.find("p → q → p") != std::string::npos ||
               err.find("q → p → q") != std::string::npos));
    }

    TEST_CASE(
        "config errors are reported together, each with its JSON pointer and a did-you-mean") {
        auto g =
            graph({node("a", "depth_reader", {}, {{"qualty", 2}, {"radius", "big"}}),
                   node("b", "color_raeder"), node("c", "relay"),
                   node("d", "color_reader",
                        {{"colour", "capture:SceneColor"}, {"extra", "a.outt"}}, {{"quality", 9}})},
                  {"c.out", "d.out"});
        const std::string err = planError(g);
        CHECK(
            err.find(
                "/passes/0/params/qualty: unknown parameter 'qualty' (did you mean 'quality'?)") !=
            std::string::npos);
        CHECK(err.find("/passes/0/params/radius: 'radius' must be a number, got \"big\"") !=
              std::string::npos);
        CHECK(err.find("/passes/1/type: unknown pass type 'color_raeder' (did you mean "
                       "'color_reader'?)") != std::string::npos);
        CHECK(err.find("/passes/2/inputs: required input 'in' of pass 'c' (relay) is not bound") !=
              std::string::npos);
        CHECK(
            err.find("/passes/3/inputs/colour: pass 'd' (color_reader) has no input 'colour' (did "
                     "you mean 'color'?)") != std::string::npos);
        CHECK(err.find(
                  "/passes/3/inputs/extra: pass 'a' (depth_reader) has no output 'outt' (did you "
                  "mean 'out'?)") != std::string::npos);
        CHECK(err.find("/passes/3/params/quality: 9 is out of range [0, 4] for 'quality'") !=
              std::string::npos);
        CHECK(err.find("7 errors") == 0);
    }

    TEST_CASE("a buffer missing from the capture is an error that lists what the file has") {
        const auto g = graph({node("a", "depth_reader")}, {"a.out"});
        PlanInputs in;
        in.availableBuffers = std::set<std::string>{"SceneColor", "SceneDepht"};
        const std::string err = planError(g, in);
        CHECK(err.find(
                  "/passes/0: the capture has no 'SceneDepth' buffer (did you mean 'SceneDepht'?); "
                  "it has [SceneColor, SceneDepht]") != std::string::npos);
    }

    TEST_CASE("an optional input's capture default binds only where the capture has it") {
        const auto g = graph({node("a", "ao_reader")}, {"a.out"});
        PlanInputs in;
        in.availableBuffers = std::set<std::string>{"GBufferAO"};
        CHECK(makePlan(g, fakeRegistry(), in).captureReads.size() == 1);
        in.availableBuffers = std::set<std::string>{"SceneColor"};  // a Blender capture, say
        CHECK(makePlan(g, fakeRegistry(), in).captureReads.empty());
        // Bound explicitly, a missing buffer stays an error.
        CHECK(planError(graph({node("a", "ao_reader", {{"ao", "capture:GBufferAO"}})}, {"a.out"}),
                        in)
                  .find("the capture has no 'GBufferAO' buffer") != std::string::npos);
    }

    TEST_CASE("an unbound optional input is accepted; channel counts must match") {
        CHECK_NOTHROW(makePlan(graph({node("d", "color_reader")}, {"d.out"}), fakeRegistry(), {}));
        const std::string err = planError(
            graph({node("d", "color_reader", {{"extra", "capture:WorldNormal"}})}, {"d.out"}));
        CHECK(err.find("/passes/0/inputs/extra: 'capture:WorldNormal' has 3 channels, the input "
                       "needs 1") != std::string::npos);
    }

    TEST_CASE("truth layers bind with the channel count the capture header gives them") {
        PlanInputs in;
        in.truthChannels = {{"Truth.AO", 1}, {"Truth.DiffuseIndirectFull", 3}};
        const Plan plan =
            makePlan(graph({node("d", "color_reader", {{"extra", "capture:Truth.AO"}})}, {"d.out"}),
                     fakeRegistry(), in);
        bool read = false;
        for (const auto& r : plan.captureReads)
            if (r.buffer == "Truth.AO")
                read = r.channels == 1 && r.kind == PortKind::Data;
        CHECK(read);
        const std::string err = planError(
            graph({node("d", "color_reader", {{"extra", "capture:Truth.DiffuseIndirectFull"}})},
                  {"d.out"}),
            in);
        CHECK(err.find("'capture:Truth.DiffuseIndirectFull' has 3 channels, the input needs 1") !=
              std::string::npos);
    }

    TEST_CASE("--set overrides config params, and its errors name the flag") {
        auto g = graph({node("a", "depth_reader", {}, {{"quality", 2}})}, {"a.out"});
        PlanInputs in;
        in.overrides.sets = {{"a.quality", 3}};
        const Plan plan = makePlan(g, fakeRegistry(), in);
        CHECK(plan.steps[0].params["quality"] == 3);
        in.overrides.sets = {{"a.quality", 7}};
        CHECK(planError(g, in).find("--set a.quality: 7 is out of range [0, 4]") !=
              std::string::npos);
        in.overrides.sets = {{"b.quality", 1}};
        CHECK(planError(g, in).find("--set b.quality: no pass named 'b'") != std::string::npos);
    }

    TEST_CASE("inputs are rebound by the config's \"inputs\" and then --input; --set on one "
              "says to use --input") {
        // c reads a by its own "inputs"; the config rebinds it to b, the command line to d.
        auto g = graph({node("a", "depth_reader"), node("b", "depth_reader"),
                        node("d", "depth_reader"), node("c", "relay", {{"in", "a.out"}})},
                       {"c.out"});
        auto sourceOf = [](const Plan& plan) {
            for (const auto& s : plan.steps)
                if (s.name == "c") return s.inputs.at("in").key;
            return std::string();
        };
        CHECK(sourceOf(makePlan(g, fakeRegistry(), {})) == "a.out");
        g.inputs = {{"c.in", "b.out"}};
        const Plan byConfig = makePlan(g, fakeRegistry(), {});
        CHECK(sourceOf(byConfig) == "b.out");
        // The source it no longer reads is culled with its pass.
        CHECK(std::none_of(byConfig.steps.begin(), byConfig.steps.end(),
                           [](const PlanStep& s) { return s.name == "a"; }));
        PlanInputs in;
        in.overrides.inputs = {{"c.in", "d.out"}};
        CHECK(sourceOf(makePlan(g, fakeRegistry(), in)) == "d.out");
        in.overrides.inputs = {{"c.inn", "d.out"}};
        CHECK(planError(g, in).find("--input c.inn: pass 'c' (relay) has no input 'inn' (did you "
                                    "mean 'in'?)") != std::string::npos);
        in.overrides.inputs = {{"c.in", "nowhere.out"}};
        CHECK(planError(g, in).find("--input c.in: ") != std::string::npos);
        in.overrides.inputs = {};
        in.overrides.sets = {{"c.in", "d.out"}};
        CHECK(planError(g, in).find("--set c.in: 'in' is an input of pass 'c', not a parameter: "
                                    "rebind it with --input c.in") != std::string::npos);
        g.inputs = nlohmann::json::object();
        g.sets = {{"c.in", "d.out"}};
        CHECK(planError(g, {}).find("/set/c.in: 'in' is an input of pass 'c', not a parameter: "
                                    "rebind it with \"inputs\": {\"c.in\": …}") != std::string::npos);
    }

    TEST_CASE("an unknown cvar is an error with a did-you-mean; an unemulated one a warning") {
        auto g = graph({node("a", "depth_reader")}, {"a.out"});
        g.cvars = {{"r.Fake.Qualty", 3}, {"r.Fake.Unemulated", 2}};
        const std::string error = planError(g, {});
        CHECK(error.find("/cvars/r.Fake.Qualty: unknown cvar 'r.Fake.Qualty' (did you mean "
                         "'r.Fake.Quality'?)") != std::string::npos);
        CHECK(error.find("--allow-unknown-cvars") != std::string::npos);
        // From the command line too, named by its flag.
        PlanInputs cli;
        cli.overrides.cvars = {{"r.Fake.Qualty", 3}};
        CHECK(planError(graph({node("a", "depth_reader")}, {"a.out"}), cli)
                  .find("--cvar r.Fake.Qualty: unknown cvar 'r.Fake.Qualty' (did you mean "
                        "'r.Fake.Quality'?)") != std::string::npos);

        // --allow-unknown-cvars: the unknown one is a warning, as is the unemulated one.
        PlanInputs allow;
        allow.allowUnknownCvars = true;
        const Plan plan = makePlan(g, fakeRegistry(), allow);
        REQUIRE(plan.warnings.size() == 2);
        CHECK(plan.warnings[0].pointer == "/cvars/r.Fake.Qualty");
        CHECK(plan.warnings[0].message.find("unknown cvar 'r.Fake.Qualty' is ignored (did you mean "
                                            "'r.Fake.Quality'?)") != std::string::npos);
        CHECK(plan.warnings[1].message.find("'r.Fake.Unemulated' is not emulated") !=
              std::string::npos);
        // A recognised but unemulated cvar alone is a warning, not an error, without the flag.
        g.cvars = {{"r.Fake.Unemulated", 2}};
        const Plan unemulated = makePlan(g, fakeRegistry(), {});
        REQUIRE(unemulated.warnings.size() == 1);
        CHECK(unemulated.warnings[0].message.find("'r.Fake.Unemulated' is not emulated") !=
              std::string::npos);
        // The value framepass runs is no news.
        g.cvars = {{"r.Fake.Unemulated", 1}};
        CHECK(makePlan(g, fakeRegistry(), {}).warnings.empty());
    }

    TEST_CASE("the cvar table is made from the parameters' own declarations") {
        const PassRegistry registry = fakeRegistry();
        const CvarTable table(registry);
        // One parameter declares r.Fake.Quality; each of the four pass types has it.
        CHECK(table.targets("r.Fake.Quality") ==
              std::vector<std::string>{"depth_reader", "color_reader", "relay", "ao_reader"});
        REQUIRE(table.find("r.Fake.Quality", "relay"));
        CHECK(table.find("r.Fake.Quality", "relay")->param == "quality");
        CHECK(table.find("r.Fake.Unemulated")->passType.empty());
        // A cvar sets the parameter it was declared on, under the config's own params.
        auto g = graph({node("a", "depth_reader")}, {"a.out"});
        g.cvars = {{"r.Fake.Quality", 3}};
        CHECK(makePlan(g, registry, {}).steps[0].params["quality"] == 3);
        g.nodes[0].params = {{"quality", 1}};
        CHECK(makePlan(g, registry, {}).steps[0].params["quality"] == 1);
    }

    TEST_CASE(
        "every built-in cvar sets a parameter that exists; inputs default only to capture "
        "buffers") {
        const PassRegistry& registry = builtinPasses();
        const CvarTable table(registry);
        for (const auto& m : table.all()) {
            if (m.passType.empty())
                continue;
            const PassType* type = registry.find(m.passType);
            REQUIRE(type);
            CHECK(std::any_of(type->params.begin(), type->params.end(),
                              [&](const ParamInfo& p) { return p.name == m.param; }));
        }
        CHECK(table.targets("r.SSGI.HalfRes") == std::vector<std::string>{"ssgi", "ssgi_denoise"});
        // A pass declares ports and at most a default capture buffer: the wiring is in the chain.
        for (const auto& type : registry.types()) {
            Diagnostics diag;
            nlohmann::json resolved;
            for (const auto& port : type.create({}, "", diag, resolved)->describe().inputs)
                CHECK_MESSAGE(
                    (port.captureDefault.empty() || findSemanticBuffer(port.captureDefault)),
                    type.id << "." << port.name << " defaults to " << port.captureDefault);
        }
    }
}
