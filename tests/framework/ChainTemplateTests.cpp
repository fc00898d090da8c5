#include "framework/ChainTemplate.h"

#include <doctest/doctest.h>

using namespace fp;

namespace {

// base → (per light: shadow_{light} → light_{light}) → show, as a preset writes it.
GraphDesc litChain() {
    GraphDesc g;
    g.nodes = {{"base", "base_type", {}, {}, "/passes/0"},
               {"show", "show_type", {}, {{"color", "base.color"}}, "/passes/2"}};
    g.outputs = {{"final.png", {"show.image"}, "/outputs/final.png", false}};
    LightTemplate t;
    t.position = 1;
    t.pointer = "/passes/1/forEachLight";
    t.colorIn = "base.color";
    t.colorOut = "light_{light}.color";
    t.passes = {{"shadow_{light}", "shadow_type", {{"light", "{lightName}"}}, {}, ""},
                {"light_{light}",
                 "light_type",
                 {{"light", "{lightName}"}, {"list", {"{light}", 2}}},
                 {{"color", "{colorIn}"}, {"shadow", "shadow_{light}.shadow"}},
                 ""}};
    t.rewire = {{"base.sceneColor", "capture:Emissive"}, {"show.color", "{colorOut}"}};
    t.outputs = {{"lit.exr", {"{colorOut}"}, "/passes/1/forEachLight/outputs/lit.exr", false},
                 {"shadows.exr", {"shadow_{light}.shadow", "light_{light}.color"}, "", false}};
    g.lightTemplates = {t};
    return g;
}

std::vector<std::string> names(const GraphDesc& g) {
    std::vector<std::string> n;
    for (const auto& node : g.nodes)
        n.push_back(node.name);
    return n;
}

}  // namespace

TEST_SUITE("chain template") {
    TEST_CASE("each light gets its passes where the template stands, adding into the one before") {
        Diagnostics diag;
        std::vector<ExpandedTemplate> expanded;
        const GraphDesc g = expandLightTemplates(litChain(), {"Key light", "rim"}, diag, &expanded);
        REQUIRE_FALSE(diag.hasErrors());
        CHECK(g.lightTemplates.empty());
        // Identifiers: letters, digits and '_' (as the light's Truth.Shadow layer).
        CHECK(names(g) == std::vector<std::string>{"base", "shadow_Key_light", "light_Key_light",
                                                   "shadow_rim", "light_rim", "show"});
        CHECK(g.nodes[1].params == nlohmann::json{{"light", "Key light"}});
        CHECK(g.nodes[2].params["list"] == nlohmann::json{"Key_light", 2});
        CHECK(g.nodes[2].inputs.at("color") == "base.color");
        CHECK(g.nodes[2].inputs.at("shadow") == "shadow_Key_light.shadow");
        CHECK(g.nodes[4].inputs.at("color") == "light_Key_light.color");  // the previous light's
        CHECK(g.nodes[4].pointer == "/passes/1/forEachLight/passes/1 (light 'rim')");
        // rewire: the chain starts from the base colour, the display shows the last light's.
        CHECK(g.nodes[0].inputs.at("sceneColor") == "capture:Emissive");
        CHECK(g.nodes[5].inputs.at("color") == "light_rim.color");
        REQUIRE(g.outputs.size() == 3);
        CHECK(g.outputs[1].sources == std::vector<std::string>{"light_rim.color"});
        CHECK(g.outputs[2].sources ==
              std::vector<std::string>{"shadow_Key_light.shadow", "light_Key_light.color",
                                       "shadow_rim.shadow", "light_rim.color"});
        REQUIRE(expanded.size() == 1);
        CHECK(expanded[0].lights == std::vector<std::string>{"Key_light", "rim"});
        CHECK(expanded[0].passes.size() == 4);
    }

    TEST_CASE("without lights a template adds nothing and changes nothing") {
        Diagnostics diag;
        const GraphDesc written = litChain();
        const GraphDesc g = expandLightTemplates(written, {}, diag);
        CHECK_FALSE(diag.hasErrors());
        CHECK(names(g) == std::vector<std::string>{"base", "show"});
        CHECK(g.nodes[0].inputs.empty());
        CHECK(g.nodes[1].inputs.at("color") == "base.color");
        CHECK(g.outputs.size() == 1);
    }

    TEST_CASE("an unknown placeholder or a rewire of a missing pass is an error at the template") {
        GraphDesc g = litChain();
        g.lightTemplates[0].passes[0].name = "shadow_{lamp}";
        g.lightTemplates[0].rewire["shwo.color"] = "{colorOut}";
        Diagnostics diag;
        expandLightTemplates(g, {"a"}, diag);
        REQUIRE(diag.errors().size() == 2);
        CHECK(diag.errors()[0].pointer == "/passes/1/forEachLight/passes/0/name");
        CHECK(diag.errors()[0].message.find("unknown placeholder '{lamp}'") != std::string::npos);
        CHECK(diag.errors()[1].pointer == "/passes/1/forEachLight/rewire/shwo.color");
        CHECK(diag.errors()[1].message.find("no pass named 'shwo'") != std::string::npos);
    }
}
