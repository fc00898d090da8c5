// The declared shapes of configs and scenes: what the readers check unknown keys against and what
// `framepass schema` writes (every shipped config and scene validates under the schemas: the
// docs test checks that with an independent validator).
#include "io/ConfigLoader.h"
#include "io/JsonShape.h"
#include "foundation/Error.h"
#include "tests/support/Scratch.h"

#include <doctest/doctest.h>

#include <fstream>

using namespace fp;

TEST_SUITE("io") {
    TEST_CASE("an unknown key is named with the closest declared one") {
        const auto unknown =
            io::configShape().unknownKeys({{"version", 1}, {"pases", nlohmann::json::array()}});
        REQUIRE(unknown.size() == 1);
        CHECK(unknown[0].first == "pases");
        CHECK(unknown[0].second.find("passes") != std::string::npos);
        CHECK(io::sceneShape().unknownKeys({{"geometry", "a.obj"}}).empty());

        // The config reader says it at the key's JSON pointer (with the planner's problems).
        const std::string path = test::scratchPath("shapes", "typo.json");
        std::ofstream(path) << R"({"version": 1, "capture": "c.exr", "pases": []})";
        const io::RunConfig config = io::loadRunConfig(path);
        REQUIRE(config.errors.size() == 1);
        CHECK(config.errors[0].pointer == "/pases");
        CHECK(config.errors[0].message.find("'passes'") != std::string::npos);
    }

    TEST_CASE("the JSON Schema of a config: required keys, closed objects, the pass entries") {
        const nlohmann::json s = io::configShape().jsonSchema();
        CHECK(s["$schema"] == "https://json-schema.org/draft/2020-12/schema");
        CHECK(s["required"] == nlohmann::json::array({"version"}));
        CHECK(s["additionalProperties"] == false);
        // A chain entry is a pass or a light template.
        const auto& entries = s["properties"]["passes"]["items"]["oneOf"];
        REQUIRE(entries.size() == 2);
        CHECK(entries[0]["required"] == nlohmann::json::array({"type"}));
        CHECK(entries[1]["required"] == nlohmann::json::array({"forEachLight"}));
        CHECK(s["properties"]["exr"]["properties"]["colorPrecision"]["enum"] ==
              nlohmann::json::array({"half", "float"}));

        const nlohmann::json scene = io::sceneShape().jsonSchema();
        const auto& light = scene["properties"]["lights"]["items"];
        CHECK(light["properties"]["type"]["enum"].size() == 4);
        CHECK(light["properties"]["samplesPerPixel"]["maximum"] == 64);
        CHECK(scene["properties"]["materials"]["additionalProperties"]["properties"].contains(
            "shadingModel"));
        CHECK_THROWS_AS(io::documentShape("camera"), UsageError);
    }
}
