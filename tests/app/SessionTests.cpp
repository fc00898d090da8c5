// The application library (app/): a session's runs in memory, its incremental re-runs (asserted
// by the executor's counts), cancellation from another thread, bench's sweep with its error
// breakdown, tune and the frame loop that writes a sequence. The capture is a small Cornell box
// rendered once by app::captureScene, with truth layers.
#include "app/BenchSweep.h"
#include "app/Capture.h"
#include "app/RunFrames.h"
#include "app/Session.h"
#include "app/Tune.h"
#include "io/CaptureSource.h"
#include "io/MemoryCapture.h"
#include "foundation/Error.h"
#include "tests/support/Scratch.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

namespace fp::test {

namespace {

// A two-frame Cornell capture (48×32, truth at 16 spp) and the Unreal 4.27 SSGI chain on it,
// measured against the full GI truth. Made once for every test of this file.
const std::string& sessionConfig() {
    static const std::string config = [] {
        const std::string capture = scratchPath("app", "cornell.####.exr");
        const std::string scene = std::string(FP_SOURCE_DIR) + "/examples/cornell/scene.json";
        app::CaptureOptions c;
        c.scene = scene;
        c.output = capture;
        c.frames = "1-2";
        c.width = 48;
        c.height = 32;
        c.truth = true;
        c.truthSpp = 16;
        c.lightSamples = 4;
        std::ostringstream quiet;
        app::captureScene(c, quiet);
        const nlohmann::json j = {
            {"version", 1},
            {"capture", capture},
            {"scene", scene},
            {"frames", "1-2"},
            {"passes",
             {{{"name", "hzb"}, {"type", "hzb"}},
              {{"name", "prev_color_reduction"},
               {"type", "prev_color_reduction"},
               {"inputs", {{"furthestHzb", "hzb.furthest"}}}},
              {{"name", "ssgi"},
               {"type", "ssgi"},
               {"inputs",
                {{"furthestHzb", "hzb.furthest"}, {"reducedColor", "prev_color_reduction.color"}}}},
              {{"name", "ssgi_denoise"},
               {"type", "ssgi_denoise"},
               {"inputs", {{"diffuse", "ssgi.diffuse"}, {"ao", "ssgi.ao"}}}},
              {{"name", "diffuse_indirect_composite"},
               {"type", "diffuse_indirect_composite"},
               {"inputs", {{"diffuse", "ssgi_denoise.diffuse"}, {"ao", "ssgi_denoise.ao"}}}},
              {{"name", "ssgi_vs_full"},
               {"type", "error_measure"},
               {"inputs",
                {{"source", "ssgi_denoise.diffuse"},
                 {"reference", "capture:Truth.DiffuseIndirectFull"}}}}}},
            {"outputs", {{"lit.####.exr", "diffuse_indirect_composite.color"}}}};
        const std::string path = scratchPath("app", "config.json");
        std::ofstream(path) << j.dump(2);
        return path;
    }();
    return config;
}

app::SetupOptions options(const std::string& frames = "1") {
    app::SetupOptions o;
    o.config = sessionConfig();
    o.frames = frames;
    return o;
}

const std::vector<std::string> kOutputs = {"ssgi_denoise.diffuse",
                                           "diffuse_indirect_composite.color"};

bool sameBits(const Image& a, const Image& b) {
    if (a.channelCount() != b.channelCount()) return false;
    for (int c = 0; c < a.channelCount(); ++c)
        if (!test::sameBits(a.plane(c), b.plane(c))) return false;
    return true;
}

// The same frames without a session: a plan, a capture source, one history, nothing cached.
std::map<std::string, Image> plainRun(const std::vector<app::SetupOptions>& settings,
                                      const std::vector<int>& frames) {
    const app::RunSetup base(settings.front());
    HistoryStore history;
    app::KeepingSink sink;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        app::SetupOptions o = settings[std::min(i, settings.size() - 1)];
        o.dumps = kOutputs;
        const app::RunSetup setup(base, o);
        io::CaptureSource::Options co = setup.captureOptions(frames[i]);
        co.firstInSequence = i == 0;
        io::CaptureSource source(co, setup.profile());
        sink.keep = i + 1 == frames.size();
        executePlan(setup.plan(), source, sink, {}, &history);
    }
    return sink.images;
}

// The steps that read `pass`'s outputs, directly or through others, and `pass` itself.
std::set<std::string> downstreamOf(const Plan& plan, const std::string& pass) {
    std::set<std::string> down = {pass};
    for (const PlanStep& step : plan.steps)
        for (const auto& [port, ref] : step.inputs)
            if (!ref.fromCapture && down.count(plan.steps[std::size_t(ref.step)].name))
                down.insert(step.name);
    return down;
}

std::set<std::string> executed(const FrameReport& r) {
    std::set<std::string> names;
    for (const auto& p : r.passes)
        if (!p.reused) names.insert(p.name);
    return names;
}

}  // namespace

TEST_SUITE("app") {
    TEST_CASE("frames from one camera position share one ray-traceable scene and its BVH") {
        const app::RunSetup setup(options());
        io::CaptureSource a(setup.captureOptions(1), setup.profile());
        io::CaptureSource b(setup.captureOptions(1), setup.profile());
        const RayScene& first = a.scene();
        CHECK(&b.scene() == &first);  // built once: Embree's BVH, and framepass's on first use
        CHECK(b.scene().bvh().nodes == first.bvh().nodes);
        // Another origin is another scene (its coordinates are relative to it), the same bits
        // as a source that builds its own.
        const std::shared_ptr<const RayScene> moved =
            setup.inputs().rayScene(first.origin() + Vec3d{1, 0, 0});
        CHECK(moved.get() != &first);
        CHECK(moved->origin().x == first.origin().x + 1.0);
    }

    TEST_CASE("a session runs a frame into memory with the bits of a plain run") {
        app::Session session(options());
        const app::FrameResult r = session.run(1, kOutputs);
        const auto plain = plainRun({options()}, {1});
        REQUIRE(r.images.size() == kOutputs.size());
        for (const auto& name : kOutputs) {
            CAPTURE(name);
            CHECK(sameBits(r.images.at(name), plain.at(name)));
        }
        CHECK(r.report.executedSteps == int(session.setup(kOutputs)->plan().steps.size()));
        CHECK(r.report.reusedSteps == 0);
    }

    TEST_CASE("after a change, only the passes downstream of it run again") {
        app::Session session(options());
        const app::FrameResult first = session.run(1, kOutputs);
        const int steps = int(session.setup(kOutputs)->plan().steps.size());

        // Nothing changed: nothing runs, the images are the same.
        const app::FrameResult again = session.run(1, kOutputs);
        CHECK(again.report.executedSteps == 0);
        CHECK(again.report.reusedSteps == steps);
        CHECK(sameBits(again.images.at(kOutputs[1]), first.images.at(kOutputs[1])));

        // A denoiser parameter: the denoiser and what reads it, not the HZB, reduction or trace.
        session.setParam("ssgi_denoise.denoiser", 0);
        const app::FrameResult changed = session.run(1, kOutputs);
        const auto expected = downstreamOf(session.setup(kOutputs)->plan(), "ssgi_denoise");
        CHECK(executed(changed.report) == expected);
        CHECK(changed.report.executedSteps == int(expected.size()));
        CHECK(changed.report.reusedSteps == steps - int(expected.size()));
        CHECK_FALSE(expected.count("ssgi"));
        CHECK_FALSE(sameBits(changed.images.at(kOutputs[0]), first.images.at(kOutputs[0])));
        // … and the bits of a run made with that setting from the start.
        app::SetupOptions denoiserOff = options();
        denoiserOff.settings.setParam("ssgi_denoise.denoiser", 0);
        const auto plain = plainRun({denoiserOff}, {1});
        for (const auto& name : kOutputs)
            CHECK(sameBits(changed.images.at(name), plain.at(name)));

        // A cvar of the trace: the trace and what follows it; the HZB and reduction stay.
        session.setCvar("r.SSGI.Quality", 2);
        const app::FrameResult quality = session.run(1, kOutputs);
        CHECK(executed(quality.report) == downstreamOf(session.setup(kOutputs)->plan(), "ssgi"));
        CHECK_FALSE(executed(quality.report).count("hzb"));
        CHECK_FALSE(executed(quality.report).count("prev_color_reduction"));
    }

    TEST_CASE("asking for another output re-runs only the pass that makes it, with the same bits") {
        app::Session session(options());
        const std::vector<std::string> one = {"ssgi_denoise.diffuse"};
        const std::vector<std::string> more = {"ssgi_denoise.diffuse", "ssgi.hitMask"};
        const app::FrameResult first = session.run(1, one);
        const app::FrameResult second = session.run(1, more);
        CHECK(executed(second.report) == std::set<std::string>{"ssgi"});
        CHECK(sameBits(second.images.at(more[0]), first.images.at(more[0])));
        app::SetupOptions withHitMask = options();
        withHitMask.dumps = more;
        app::Session fresh(withHitMask);
        CHECK(sameBits(second.images.at(more[1]), fresh.run(1, more).images.at(more[1])));
        // The trace made the hit mask: asking for less runs nothing.
        CHECK(session.run(1, one).report.executedSteps == 0);
    }

    TEST_CASE("a sequence carries history, and a frame run again starts from the history it had") {
        app::Session session(options("1-2"));
        session.run(1, kOutputs);
        const app::FrameResult second = session.run(2, kOutputs);
        CHECK(second.report.executedSteps == int(second.report.passes.size()));
        CHECK(sameBits(second.images.at(kOutputs[0]), plainRun({options("1-2")}, {1, 2}).at(kOutputs[0])));

        // Frame 2 again, unchanged: the temporal denoiser's history is the one it had, so
        // nothing runs.
        const app::FrameResult again = session.run(2, kOutputs);
        CHECK(again.report.executedSteps == 0);

        // Frame 2 with another quality, from frame 1's history made at the old quality: the
        // bits of a plain sequence that changes the setting between its frames.
        session.setCvar("r.SSGI.Quality", 1);
        const app::FrameResult changed = session.run(2, kOutputs);
        app::SetupOptions q1 = options("1-2");
        q1.settings.setCvar("r.SSGI.Quality", 1);
        const auto plain = plainRun({options("1-2"), q1}, {1, 2});
        for (const auto& name : kOutputs)
            CHECK(sameBits(changed.images.at(name), plain.at(name)));
        CHECK_FALSE(executed(changed.report).count("hzb"));
    }

    TEST_CASE("cancel() from another thread stops a run between passes; the next run is whole") {
        app::Session session(options());
        bool cancelled = false;
        session.onPass = [&](int done, int, const PassReport&) {
            if (done == 2 && !cancelled) {
                cancelled = true;
                std::thread([&] { session.cancel(); }).join();
            }
        };
        CHECK_THROWS_AS(session.run(1, kOutputs), Cancelled);
        session.onPass = {};
        const app::FrameResult r = session.run(1, kOutputs);
        // The two passes that finished before the cancel stand; the rest run now.
        const int steps = int(session.setup(kOutputs)->plan().steps.size());
        CHECK(r.report.reusedSteps == 2);
        CHECK(r.report.executedSteps == steps - 2);
        const auto plain = plainRun({options()}, {1});
        for (const auto& name : kOutputs)
            CHECK(sameBits(r.images.at(name), plain.at(name)));
    }

    TEST_CASE("bench's sweep measures each setting with its error and takes it apart") {
        app::BenchOptions b;
        b.session = options();
        b.runs = 1;
        b.warmup = 0;
        b.decomposeRays = 16;
        app::Bencher bencher(b);
        const auto grid = app::sweepGrid({app::parseSweep("r.SSGI.Quality=1,4")});
        REQUIRE(grid.size() == 2);
        bencher.expectRuns(2);
        const app::BenchSetting low = bencher.measure(grid[0], false);
        const app::BenchSetting high = bencher.measure(grid[1], true);
        CHECK(low.label == "r.SSGI.Quality=1");
        CHECK(high.label == "r.SSGI.Quality=4");
        auto work = [](const app::BenchSetting& s, const std::string& pass) {
            for (const auto& p : s.passes)
                if (p.name == pass) return p.work;
            return uint64_t(0);
        };
        // Quality 4 marches more rays, further, than quality 1 (algorithms §4.2).
        CHECK(work(high, "ssgi") > work(low, "ssgi"));
        REQUIRE(high.hasError());
        CHECK(high.errors.front().name == "ssgi_vs_full");
        CHECK(std::isfinite(high.error()));
        CHECK(high.error() > 0);
        // The error measure is not part of the chain's time.
        double chain = 0;
        for (const auto& p : high.passes)
            if (p.name != "ssgi_vs_full") chain += p.seconds.median;
        CHECK(high.chainSeconds() == doctest::Approx(chain));
        // Against the full truth the ladder has its four steps, found through the passes'
        // declared roles: noise, approximation, screen-space limit, multi-bounce.
        REQUIRE(high.errors.front().decomposition);
        const auto& d = *high.errors.front().decomposition;
        REQUIRE(d.steps.size() == 4);
        CHECK(d.steps[0].name == "noise");
        CHECK(d.steps[3].name == "multi-bounce");
        CHECK(d.steps[1].to.find("screen_space_oracle") == 0);
        CHECK_FALSE(low.errors.front().decomposition);
    }

    TEST_CASE("tune takes the cheapest setting that meets the target, or says none does") {
        app::TuneOptions t;
        t.bench.session = options();
        t.bench.runs = 1;
        t.bench.warmup = 0;
        t.bench.decomposeRays = 0;
        t.bench.sweeps = {app::parseSweep("r.SSGI.Quality=1,4")};
        t.refine = 0;
        t.target = "ssgi_vs_full<=1000";  // every setting meets it
        const app::TuneResult met = app::tune(t);
        REQUIRE(met.tried.size() == 2);
        REQUIRE(met.choice);
        const auto& choice = met.tried[*met.choice];
        CHECK(choice.value <= 1000);
        CHECK(app::systemSettings(choice.point).find("[SystemSettings]\nr.SSGI.Quality=") == 0);
        CHECK(met.toJson("c.json")["met"] == true);

        t.target = "ssgi_vs_full<=0";  // none can
        const app::TuneResult unmet = app::tune(t);
        CHECK_FALSE(unmet.choice);
        for (const auto& s : unmet.tried)
            CHECK(unmet.tried[unmet.mostAccurate].value <= s.value);
        CHECK(unmet.toJson("c.json")["met"] == false);

        t.target = "no_such_pass<=1";
        CHECK_THROWS_AS(app::tune(t), UsageError);
    }

    TEST_CASE("runFrames writes each frame's outputs and a report of every frame") {
        app::RunOptions r;
        r.setup = options("1-2");
        r.outputDir = scratchPath("app/run", "");
        r.report = scratchPath("app/run", "report.json");
        std::ostringstream out, err;
        const app::RunOutcome outcome = app::runFrames(r, out, err);
        CHECK(outcome.failedFrames.empty());
        CHECK(outcome.frames == 2);
        REQUIRE(outcome.report["frames"].size() == 2);
        for (const auto& f : outcome.report["frames"])
            CHECK(f["status"] == "ok");
        CHECK(std::filesystem::exists(r.outputDir + "/lit.0001.exr"));
        CHECK(std::filesystem::exists(r.outputDir + "/lit.0002.exr"));
        CHECK(std::filesystem::exists(r.report));
    }
    TEST_CASE("run, a session and bench run frames through one driver: the same figures") {
        // Frame 2 of the sequence, after frame 1 (the denoiser's history), three ways: the error
        // its measure reports is the same double in each, and the session's image is the plain
        // executor loop's.
        app::Session session(options("1-2"));
        std::vector<std::string> outputs = kOutputs;
        outputs.push_back("ssgi_vs_full.heat");  // the measure runs when its output is asked for
        session.run(1, outputs);
        const app::FrameResult second = session.run(2, outputs);
        CHECK(sameBits(second.images.at(kOutputs[0]), plainRun({options("1-2")}, {1, 2}).at(kOutputs[0])));
        auto rmseOf = [](const std::vector<PassReport>& passes) {
            for (const auto& p : passes)
                if (p.name == "ssgi_vs_full") return p.metrics.at("rmse");
            return -1.0;
        };
        const double sessionRmse = rmseOf(second.report.passes);
        REQUIRE(sessionRmse > 0);

        app::RunOptions r;
        r.setup = options("1-2");
        r.outputDir = scratchPath("app/driver", "");
        std::ostringstream out, err;
        const app::RunOutcome outcome = app::runFrames(r, out, err);
        REQUIRE(outcome.report["frames"].size() == 2);
        for (const auto& p : outcome.report["frames"][1]["passes"])
            if (p["name"] == "ssgi_vs_full") CHECK(p["metrics"]["rmse"].get<double>() == sessionRmse);

        app::BenchOptions b;
        b.session = options("1-2");
        b.runs = 1;
        b.warmup = 1;  // a second timed sequence starts afresh: no history carried across runs
        const app::BenchResult bench = app::runBench(b);
        REQUIRE(bench.settings.size() == 1);
        REQUIRE(bench.settings.front().hasError());
        CHECK(bench.settings.front().errors.front().metrics.at("rmse") == sessionRmse);
    }

    TEST_CASE("a session on a capture in memory gives the bits of one on its file") {
        const app::RunSetup probe(options());
        auto memory = std::make_shared<io::MemoryCapture>(
            io::readCapture(probe.capturePath(1), probe.profile()));
        CHECK(memory->frame() == 1);
        REQUIRE(memory->camera());
        CHECK(memory->availableBuffers().count("Truth.DiffuseIndirectFull"));
        app::SetupOptions o = options();
        o.memoryCapture = memory;
        app::Session inMemory(o);
        CHECK(inMemory.frames() == std::vector<int>{1});
        const app::FrameResult r = inMemory.run(1, kOutputs);
        const auto plain = plainRun({options()}, {1});
        for (const auto& name : kOutputs) {
            CAPTURE(name);
            CHECK(sameBits(r.images.at(name), plain.at(name)));
        }
        // The executor reads the buffers in place: the capture's own planes, not copies.
        io::CaptureSource::Options co = probe.captureOptions(1);
        io::MemoryCaptureSource source(memory, co);
        const Texture depth = source.loadBuffer("SceneDepth", 1);
        CHECK(depth.image().plane(0).row(0) == memory->buffers().at("SceneDepth").plane(0).row(0));
    }

    TEST_CASE("a capture in memory takes only buffers it can run, and replaces bad pixels") {
        io::MemoryCapture c("<test>", 7);
        CHECK_THROWS_AS(c.add("Albedo", Image(4, 2, {"R", "G", "B"})), UsageError);
        CHECK_THROWS_AS(c.add("WorldNormal", Image(4, 2, {"X", "Y"})), UsageError);
        CHECK_THROWS_AS(c.add("Truth.AO", Image(4, 2, {"A", "B"})), UsageError);
        Image depth(4, 2, {"Z"}, 5.0f);
        depth.plane(0).at(1, 0) = -1.0f;
        depth.plane(0).at(2, 0) = std::nanf("");
        c.add("SceneDepth", depth);
        CHECK(std::isinf(c.buffers().at("SceneDepth").plane(0).at(1, 0)));
        CHECK(std::isinf(c.buffers().at("SceneDepth").plane(0).at(2, 0)));
        CHECK(c.sanitized().nonFinite == 2);
        CHECK(c.notes().size() == 1);
        CHECK_THROWS_WITH_AS(c.add("BaseColor", Image(4, 3, {"R", "G", "B"})),
                             doctest::Contains("'BaseColor' is 4×3, but 'SceneDepth' is 4×2"),
                             UsageError);
        c.add("Truth.AO", Image(4, 2, {"Y"}));
        CHECK(c.truthChannels() == std::map<std::string, int>{{"Truth.AO", 1}});
        CHECK(c.availableBuffers() == std::set<std::string>{"SceneDepth", "Truth.AO"});
    }

    TEST_CASE("a session reads a cvar as set, else as the config gives it, else its default") {
        app::Session session(options());
        const auto& params = builtinPasses().find("ssgi")->params;
        const auto quality = std::find_if(params.begin(), params.end(),
                                          [](const ParamInfo& p) { return p.name == "quality"; });
        REQUIRE(quality != params.end());
        CHECK(session.cvarValue("r.SSGI.Quality") == quality->defaultValue);
        session.setCvar("r.ssgi.quality", 2);  // Unreal's console ignores case
        CHECK(session.cvarValue("r.SSGI.Quality") == 2);
        CHECK_THROWS_WITH_AS(session.cvarValue("r.SSGI.Qualty"),
                             doctest::Contains("r.SSGI.Quality"), UsageError);
        const auto names = session.cvarNames();
        CHECK(std::find(names.begin(), names.end(), "r.SSGI.Quality") != names.end());
    }

    TEST_CASE("a config's errors carry its path and each problem's JSON pointer") {
        nlohmann::json j = nlohmann::json::parse(std::ifstream(sessionConfig()));
        j["cvars"] = {{"r.SSGI.Quality", "high"}};
        j["passes"][2]["params"] = {{"rays", -3}};
        const std::string path = scratchPath("app", "bad_config.json");
        std::ofstream(path) << j.dump();
        app::SetupOptions o = options();
        o.config = path;
        try {
            app::Session session(o);
            FAIL("a bad config planned");
        } catch (const UsageError& e) {
            CHECK(e.path() == path);
            std::set<std::string> pointers;
            for (const auto& p : e.problems()) pointers.insert(p.pointer);
            CHECK(pointers.count("/cvars/r.SSGI.Quality"));
            CHECK(pointers.count("/passes/2/params/rays"));
        }
    }
}

}  // namespace fp::test
