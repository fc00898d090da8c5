#include "app/Settings.h"

#include "foundation/Error.h"
#include "framework/CvarTable.h"
#include "io/ConfigLoader.h"

#include <fmt/format.h>

#include <algorithm>

namespace fp::app {

const CvarTable& builtinCvarTable() {
    static const CvarTable table(builtinPasses());
    return table;
}

namespace {
std::string trimmed(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::pair<std::string, std::string> splitAssignment(const std::string& text, const char* flag) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0)
        throw UsageError(fmt::format("{} {}: expected NAME=VALUE", flag, text));
    return {text.substr(0, eq), text.substr(eq + 1)};
}
}  // namespace

void Settings::setCvar(const std::string& name, nlohmann::json value) {
    const CvarTable& table = builtinCvarTable();
    const std::string spelled = table.spelling(name);
    for (auto it = cvars.begin(); it != cvars.end();) {
        if (table.spelling(it.key()) == spelled) it = cvars.erase(it);
        else ++it;
    }
    cvars[name] = std::move(value);
}

void Settings::setParam(const std::string& target, nlohmann::json value) {
    std::erase_if(sets, [&](const auto& s) { return s.first == target; });
    sets.emplace_back(target, std::move(value));
}

void Settings::merge(const Settings& more) {
    for (const auto& [name, value] : more.cvars.items()) setCvar(name, value);
    for (const auto& [target, value] : more.sets) setParam(target, value);
}

const nlohmann::json* Settings::cvar(const std::string& name) const {
    const CvarTable& table = builtinCvarTable();
    const std::string spelled = table.spelling(name);
    for (auto it = cvars.begin(); it != cvars.end(); ++it)
        if (table.spelling(it.key()) == spelled) return &*it;
    return nullptr;
}

nlohmann::json Settings::toJson() const {
    nlohmann::json set = nlohmann::json::object();
    for (const auto& [target, value] : sets) set[target] = value;
    return {{"cvars", cvars}, {"set", set}};
}

std::string Settings::cvarWhere(const std::string& name) const {
    return fmt::format(fmt::runtime(cvarOrigin), name);
}

std::string Settings::setWhere(const std::string& target) const {
    return fmt::format(fmt::runtime(setOrigin), target);
}

nlohmann::json Settings::valueFromText(const std::string& text) { return io::parseCliValue(text); }

void Settings::setCvarText(const std::string& text) {
    // Unreal's console form "r.SSGI.Quality 4" (no '='), else NAME=VALUE.
    const std::string t = trimmed(text);
    const auto eq = t.find('=');
    const auto space = t.find_first_of(" \t");
    if (eq == std::string::npos && space != std::string::npos && space > 0) {
        setCvar(t.substr(0, space), valueFromText(trimmed(t.substr(space))));
        return;
    }
    auto [name, value] = splitAssignment(t, "--cvar");
    setCvar(trimmed(name), valueFromText(trimmed(value)));
}

void Settings::setParamText(const std::string& text) {
    auto [target, value] = splitAssignment(text, "--set");
    setParam(target, valueFromText(value));
}

}  // namespace fp::app
