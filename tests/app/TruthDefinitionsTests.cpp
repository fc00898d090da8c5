// A measure against a truth of another definition says so (issue 46): the capture's header
// records what each truth measures, and error_measure's plan and compare warn, naming the
// setting that matches.
#include "app/TruthDefinitions.h"

#include "tests/support/TestScenes.h"

#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <doctest/doctest.h>

#include <cmath>

using namespace fp;
using namespace fp::app;

namespace {

// A capture header as `capture --truth --truth-ao-radius <metres>` writes it (100 units/m).
Imf::Header captureHeader(double aoRadiusMetres) {
    Imf::Header h(4, 4);
    h.insert("framepass:sceneUnitsPerMeter", Imf::DoubleAttribute(100.0));
    for (const auto& [name, value] : truthDefinitionAttributes(aoRadiusMetres * 100.0, 256))
        h.insert(name, Imf::StringAttribute(value));
    return h;
}

std::vector<Diagnostic> warningsFor(std::vector<NodeDesc> nodes, const std::string& measured,
                                    double aoRadiusMetres) {
    nodes.push_back(test::node("error_measure", {},
                               {{"source", measured}, {"reference", "capture:Truth.AO"}}));
    const Plan plan = test::planFor(nodes, {"error_measure.absError"});
    return truthDefinitionWarnings(plan, readTruthDefinitions(captureHeader(aoRadiusMetres)));
}

}  // namespace

TEST_CASE("the capture's header records each truth's definition, and reads back") {
    const auto attrs = truthDefinitionAttributes(150.0, 256);
    CHECK(attrs.at("framepass:truth.AO.radius") == "150");
    CHECK(attrs.at("framepass:truth.AOAnyDistance.radius") == "inf");
    CHECK(attrs.at("framepass:truth.DiffuseIndirectOneBounce.bounces") == "1");
    CHECK(attrs.at("framepass:truth.DiffuseIndirectFull.bounces") == "256");

    const TruthDefinitions d = readTruthDefinitions(captureHeader(1.5));
    CHECK(d.at("Truth.AO").at("radius") == doctest::Approx(1.5));  // metres
    CHECK(std::isinf(d.at("Truth.AOAnyDistance").at("radius")));
    CHECK(d.at("Truth.DiffuseIndirectOneBounce").at("bounces") == 1);
    CHECK(d.at("Truth.DiffuseIndirectFull").at("bounces") == 256);

    // A header with none (another tool's EXR) has no definitions.
    CHECK(readTruthDefinitions(Imf::Header(4, 4)).empty());
    // A capture made before the attributes recorded the AO radius alone, in scene units.
    Imf::Header old(4, 4);
    old.insert("framepass:truthAoRadius", Imf::StringAttribute("100"));
    const TruthDefinitions o = readTruthDefinitions(old);
    CHECK(o.at("Truth.AO").at("radius") == doctest::Approx(1.0));
    CHECK(std::isinf(o.at("Truth.AOAnyDistance").at("radius")));
}

TEST_CASE("rt_ambient_occlusion at another radius than Truth.AO's is warned, naming the match") {
    SUBCASE("Unreal's 200 cm against a 1 m truth") {
        const auto w = warningsFor({test::node("rt_ambient_occlusion")},
                                   "rt_ambient_occlusion.ao", 1.0);
        REQUIRE(w.size() == 1);
        CHECK(w[0].pointer == "/passes/1");
        const std::string& m = w[0].message;
        INFO(m);
        CHECK(m.find("rt_ambient_occlusion.radius = 200 cm, its default") != std::string::npos);
        CHECK(m.find("counts occluders within 1 m") != std::string::npos);
        CHECK(m.find("set rt_ambient_occlusion.radius=100") != std::string::npos);
        CHECK(m.find("--truth-ao-radius 2") != std::string::npos);
    }
    SUBCASE("the same radius: no warning, through the AO denoiser too") {
        CHECK(warningsFor({test::node("rt_ambient_occlusion", {{"radius", 100}})},
                          "rt_ambient_occlusion.ao", 1.0)
                  .empty());
        CHECK(warningsFor({test::node("rt_ambient_occlusion")}, "rt_ambient_occlusion.ao", 2.0)
                  .empty());
    }
    SUBCASE("through the AO denoiser the pass upstream is judged") {
        const auto w = warningsFor(
            {test::node("rt_ambient_occlusion"),
             test::node("ao_denoise", {},
                        {{"ao", "rt_ambient_occlusion.ao"},
                         {"hitDistance", "rt_ambient_occlusion.hitDistance"}})},
            "ao_denoise.ao", 1.0);
        REQUIRE(w.size() == 1);
        CHECK(w[0].message.find("(through ao_denoise)") != std::string::npos);
    }
}

TEST_CASE("SSGI's any-distance AO against Truth.AO is warned: Truth.AOAnyDistance matches") {
    const auto w = warningsFor({test::node("hzb"),
                                test::node("prev_color_reduction", {},
                                           {{"furthestHzb", "hzb.furthest"}}),
                                test::node("ssgi", {},
                                           {{"furthestHzb", "hzb.furthest"},
                                            {"reducedColor", "prev_color_reduction.color"}})},
                               "ssgi.ao", 1.0);
    REQUIRE(w.size() == 1);
    INFO(w[0].message);
    CHECK(w[0].message.find("counts occluders at any distance") != std::string::npos);
    CHECK(w[0].message.find("judge it against Truth.AOAnyDistance") != std::string::npos);
}

TEST_CASE("compare warns when the two layers' recorded definitions differ") {
    const TruthDefinitions a = readTruthDefinitions(captureHeader(1.0));
    const TruthDefinitions b = readTruthDefinitions(captureHeader(2.0));
    const auto w = truthDefinitionMismatch("a.exr[Truth.AO]", "Truth.AO", a, "b.exr[Truth.AO]",
                                           "Truth.AO", b);
    REQUIRE(w.size() == 1);
    CHECK(w[0].find("a.exr[Truth.AO] counts occluders within 1 m but b.exr[Truth.AO] counts "
                    "occluders within 2 m") != std::string::npos);
    CHECK(truthDefinitionMismatch("a", "Truth.AO", a, "b", "Truth.AO", a).empty());
    CHECK(truthDefinitionMismatch("a", "Truth.AO", a, "b", "Truth.AOAnyDistance", a).size() == 1);
    CHECK(truthDefinitionMismatch("a", "Truth.AO", a, "b", "Truth.AO", {}).empty());
}

TEST_CASE("RTAO against Truth.AOAnyDistance is pointed at a Truth.AO of its radius") {
    std::vector<NodeDesc> nodes = {test::node("rt_ambient_occlusion"),
                                   test::node("error_measure", {},
                                              {{"source", "rt_ambient_occlusion.ao"},
                                               {"reference", "capture:Truth.AOAnyDistance"}})};
    const Plan plan = test::planFor(nodes, {"error_measure.absError"});
    const auto w = truthDefinitionWarnings(plan, readTruthDefinitions(captureHeader(1.0)));
    REQUIRE(w.size() == 1);
    INFO(w[0].message);
    CHECK(w[0].message.find("judge it against Truth.AO of a capture made with --truth "
                            "--truth-ao-radius 2") != std::string::npos);
    // A capture whose Truth.AO is already at its radius: that layer.
    const auto w2 = truthDefinitionWarnings(plan, readTruthDefinitions(captureHeader(2.0)));
    REQUIRE(w2.size() == 1);
    CHECK(w2[0].message.find("judge it against Truth.AO;") == std::string::npos);
    CHECK(w2[0].message.find("judge it against Truth.AO") != std::string::npos);
    CHECK(w2[0].message.find("of a capture made") == std::string::npos);
}

TEST_CASE("bounces: one against several warns; several against the tracer's 256 does not") {
    auto warnings = [](int maxBounces, const char* truth) {
        std::vector<NodeDesc> nodes = {
            test::node("rt_global_illumination", {{"maxBounces", maxBounces}}),
            test::node("error_measure", {},
                       {{"source", "rt_global_illumination.diffuse"},
                        {"reference", std::string("capture:") + truth}})};
        const Plan plan = test::planFor(nodes, {"error_measure.absError"});
        return truthDefinitionWarnings(plan, readTruthDefinitions(captureHeader(1.0)));
    };
    const auto w = warnings(-1, "Truth.DiffuseIndirectFull");
    REQUIRE(w.size() == 1);
    INFO(w[0].message);
    CHECK(w[0].message.find("gathers one bounce") != std::string::npos);
    CHECK(w[0].message.find("set rt_global_illumination.maxBounces above 1") != std::string::npos);
    CHECK(w[0].message.find("judge it against Truth.DiffuseIndirectOneBounce") != std::string::npos);
    CHECK(warnings(3, "Truth.DiffuseIndirectFull").empty());
    CHECK(warnings(1, "Truth.DiffuseIndirectOneBounce").empty());
    CHECK(warnings(3, "Truth.DiffuseIndirectOneBounce").size() == 1);
}
