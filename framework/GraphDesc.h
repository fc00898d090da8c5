#pragma once
// The chain as the config describes it: plain data with the JSON pointer of every piece, so the
// planner can say exactly where a problem is. io/ConfigLoader fills it; the planner reads it.
#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace fp {

struct NodeDesc {
    std::string name;  //!< unique; how other passes address its outputs ("name.port")
    std::string type;  //!< pass type id
    nlohmann::json params = nlohmann::json::object();
    std::map<std::string, std::string> inputs;  //!< port → "capture:Buffer" or "pass.port"
    std::string pointer;                        //!< e.g. /passes/2
};

struct OutputDesc {
    std::string file;                  //!< file name or pattern, relative to the output folder
    std::vector<std::string> sources;  //!< "pass.port" written as layers of this file
    std::string pointer;
    bool isDump = false;  //!< from --dump: one intermediate, written for debugging
};

/// Passes repeated once per light of the scene (Unreal's RenderLights, algorithms §10 step 6),
/// written in a chain as {"forEachLight": {...}} where the expansion goes. Its strings may hold the
/// placeholders {light} (the light's identifier, as in its Truth.Shadow layer), {lightName} (its
/// name in the scene), {colorIn} (the colour this light adds into: `colorIn` for the first light,
/// the previous light's `colorOut` after it) and {colorOut} (in `rewire` and `outputs`: the last
/// light's `colorOut`). expandLightTemplates (ChainTemplate.h) turns it into plain nodes.
struct LightTemplate {
    std::size_t position = 0;  //!< index into GraphDesc::nodes the expansion is inserted before
    std::vector<NodeDesc> passes;
    std::string colorIn;   //!< the colour the first light adds into
    std::string colorOut;  //!< one light's result, e.g. "lighting_{light}.color"
    /// "pass.inputPort" → source: inputs of the surrounding chain that change once a light exists
    /// (the chain starts from the base pass's colour, the display shows the lit one).
    std::map<std::string, std::string> rewire;
    /// Files written once a light exists; a source with {light} is repeated per light.
    std::vector<OutputDesc> outputs;
    std::string pointer;  //!< where the template is written, e.g. /passes/5/forEachLight
};

struct GraphDesc {
    std::vector<NodeDesc> nodes;
    std::vector<OutputDesc> outputs;
    std::vector<LightTemplate> lightTemplates;        //!< empty once expanded
    nlohmann::json cvars = nlohmann::json::object();  //!< Unreal cvar name → value
    nlohmann::json sets = nlohmann::json::object();   //!< PASS.PARAM → value, as --set
    /// PASS.INPUT → source ("pass.port" or "capture:Buffer"), as --input: rebinds that input
    /// on top of the pass's own "inputs".
    nlohmann::json inputs = nlohmann::json::object();
    std::string engine = "ue4.27";
    std::string device = "cpu";  //!< "cpu" or "cuda": where the passes with a CUDA kernel run
};

/// Command-line adjustments applied by the planner on top of the config.
struct PlanOverrides {
    nlohmann::json cvars = nlohmann::json::object();           //!< --cvar NAME=VALUE
    std::vector<std::pair<std::string, nlohmann::json>> sets;  //!< --set PASS.PARAM=VALUE
    std::vector<std::pair<std::string, std::string>> inputs;   //!< --input PASS.INPUT=SOURCE
    std::vector<std::string> dumps;                            //!< --dump PASS.PORT, or "all"
    std::string device;  //!< --device cpu|cuda ("" = the config's)
    /// How a message names a cvar, a PASS.PARAM and a PASS.INPUT of the three above: fmt patterns taking the name,
    /// in the terms of the door that set them (the command line's flags, a Python call).
    std::string cvarOrigin = "--cvar {}", setOrigin = "--set {}", inputOrigin = "--input {}";
    /// The same for a dump (an output asked for by name).
    std::string dumpOrigin = "--dump {}";
    /// No pass is culled: each runs whether or not a requested output depends on it (the
    /// workbench shows every pass, its time and its outputs).
    bool runEveryPass = false;
    /// Only the dumps go to the sink. The config's outputs still decide what runs and is made,
    /// but are not handed over (the workbench serves the buffers it shows, not the config's
    /// files, and on the GPU each output handed over is a copy to the host).
    bool dumpsOnly = false;
};

}  // namespace fp
