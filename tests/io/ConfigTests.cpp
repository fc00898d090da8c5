#include "io/ConfigLoader.h"

#include <doctest/doctest.h>

using namespace fp;

TEST_SUITE("io") {
    TEST_CASE("a preset's light template is read as data, its outputs dropped for the user's own") {
        const nlohmann::json bare = {{"version", 1}, {"capture", "c.exr"}};
        const io::RunConfig rc = io::parseRunConfig(bare, "test", "");
        CHECK(rc.errors.empty());
        REQUIRE(rc.graph.lightTemplates.size() == 1);
        const LightTemplate& t = rc.graph.lightTemplates[0];
        CHECK(t.pointer == "(preset ue4.27)/passes/5/forEachLight");
        CHECK(t.position == 5);  // before SSR, the reflections and the display: the sixth pass
        CHECK(rc.graph.nodes[t.position].name == "ssr");
        CHECK(rc.graph.nodes[t.position + 2].name == "display");
        CHECK(t.passes.size() == 3);
        CHECK(t.outputs.size() == 2);

        nlohmann::json own = bare;
        own["outputs"] = {{"x.####.exr", "hzb.furthest"}};
        const io::RunConfig rc2 = io::parseRunConfig(own, "test", "");
        CHECK(rc2.graph.outputs.size() == 1);
        CHECK(rc2.graph.lightTemplates.at(0).outputs.empty());
    }

    TEST_CASE("a config's own forEachLight is checked key by key") {
        const nlohmann::json j = {
            {"version", 1},
            {"capture", "c.exr"},
            {"passes",
             {{{"name", "a"}, {"type", "hzb"}},
              {{"forEachLight", {{"passes", nlohmann::json::array()}, {"colourIn", "a.x"}}}}}}};
        const io::RunConfig rc = io::parseRunConfig(j, "test", "");
        REQUIRE(rc.errors.size() == 1);
        CHECK(rc.errors[0].pointer == "/passes/1/forEachLight/colourIn");
        CHECK(rc.errors[0].message.find("did you mean 'colorIn'?") != std::string::npos);
        REQUIRE(rc.graph.lightTemplates.size() == 1);
        CHECK(rc.graph.lightTemplates[0].position == 1);
    }
}
