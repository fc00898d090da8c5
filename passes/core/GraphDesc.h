#pragma once
// The chain as the config describes it: plain data with the JSON pointer of every piece, so the
// planner can say exactly where a problem is. io/ConfigLoader fills it; the planner reads it.
#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace fp {

struct NodeDesc {
    std::string name;     //!< unique; how other passes address its outputs ("name.port")
    std::string type;     //!< pass type id
    nlohmann::json params = nlohmann::json::object();
    std::map<std::string, std::string> inputs;  //!< port → "capture:Buffer" or "pass.port"
    std::string pointer;  //!< e.g. /passes/2
};

struct OutputDesc {
    std::string file;                  //!< file name or pattern, relative to the output folder
    std::vector<std::string> sources;  //!< "pass.port" written as layers of this file
    std::string pointer;
    bool isDump = false;               //!< from --dump: one intermediate, written for debugging
};

struct GraphDesc {
    std::vector<NodeDesc> nodes;
    std::vector<OutputDesc> outputs;
    nlohmann::json cvars = nlohmann::json::object();  //!< Unreal cvar name → value
    std::string engine = "ue4.27";
};

/// Command-line adjustments applied by the planner on top of the config.
struct PlanOverrides {
    nlohmann::json cvars = nlohmann::json::object();  //!< --cvar NAME=VALUE
    std::vector<std::pair<std::string, nlohmann::json>> sets;  //!< --set PASS.PARAM=VALUE
    std::vector<std::string> dumps;  //!< --dump PASS.PORT, or "all"
};

}  // namespace fp
