#pragma once
// The settings a door changes on top of a config: Unreal cvars, PASS.PARAM values and PASS.INPUT
// rebindings, typed as JSON from every door to the planner. Text becomes a value only where a
// user typed text: the command line's --cvar, --set and --input, and an Unreal .ini file; the
// Python module and the server hand their values over as they are.
#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace fp {
class CvarTable;
struct ParamInfo;
}

namespace fp::app {

/// The built-in passes' cvar table, made once (the registry does not change while running).
const CvarTable& builtinCvarTable();
/// The declaration of parameter `param` of built-in pass type `passType`; nullptr if either is
/// unknown.
const ParamInfo* builtinParam(const std::string& passType, const std::string& param);

struct Settings {
    /// Unreal cvar → value, in the spelling last set (names match without regard to case; the
    /// members below keep one spelling of each, code that fills this directly must too).
    nlohmann::json cvars = nlohmann::json::object();
    /// PASS.PARAM → value, in the order set; a later value of one replaces it.
    std::vector<std::pair<std::string, nlohmann::json>> sets;
    /// PASS.INPUT → source ("pass.port" or "capture:Buffer"), as sets are kept.
    std::vector<std::pair<std::string, std::string>> inputs;
    /// How the door that made these settings names one in a message, an fmt pattern taking the
    /// name: the command line's "--cvar {}", "--set {}" and "--input {}", the Python module's
    /// "set_cvar('{}')".
    std::string cvarOrigin = "--cvar {}", setOrigin = "--set {}", inputOrigin = "--input {}";

    /// Sets a cvar, replacing any setting of the same cvar (whatever its case).
    void setCvar(const std::string& name, nlohmann::json value);
    /// Sets PASS.PARAM, replacing an earlier value of it.
    void setParam(const std::string& target, nlohmann::json value);
    /// Rebinds input PASS.INPUT to `source`, replacing an earlier rebinding of it.
    void setInput(const std::string& target, std::string source);
    /// Every setting of `more` on top of these (its cvars, parameters and inputs win).
    void merge(const Settings& more);
    /// The value set for a cvar (any case), or nullptr when it is not set here.
    const nlohmann::json* cvar(const std::string& name) const;

    /// {"cvars": {NAME: VALUE}, "set": {PASS.PARAM: VALUE}, "inputs": {PASS.INPUT: SOURCE}}:
    /// what a config's keys of those names hold, and what the server's settings requests send.
    nlohmann::json toJson() const;
    /// What `name` is called in a message from the door that set it.
    std::string cvarWhere(const std::string& name) const;
    std::string setWhere(const std::string& target) const;
    std::string inputWhere(const std::string& target) const;

    /// A value as typed on a command line or in an .ini file: JSON where it reads as JSON
    /// (4, 0.5, true, "text"), else the text itself.
    static nlohmann::json valueFromText(const std::string& text);
    /// --cvar's text, as Unreal's console takes it: "r.SSGI.Quality 4" or r.SSGI.Quality=4.
    void setCvarText(const std::string& text);
    /// --set's text: PASS.PARAM=VALUE.
    void setParamText(const std::string& text);
    /// --input's text: PASS.INPUT=SOURCE.
    void setInputText(const std::string& text);
};

/// The cvars of an Unreal .ini file (its [SystemSettings] and [ConsoleVariables]),
/// in UTF-8 (with or without a byte-order mark) or UTF-16 (either byte order; Unreal on Windows
/// writes both). A file that gives no cvar is an error when `strict`, else a warning.
Settings readCvarsFile(const std::string& path, bool strict = false);

}  // namespace fp::app
