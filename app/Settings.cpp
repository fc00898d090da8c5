#include "app/Settings.h"

#include "app/Invocation.h"
#include "foundation/Error.h"
#include "framework/CvarTable.h"
#include "io/ConfigLoader.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

namespace fp::app {

const CvarTable& builtinCvarTable() {
    static const CvarTable table(builtinPasses());
    return table;
}

const ParamInfo* builtinParam(const std::string& passType, const std::string& param) {
    if (const PassType* type = builtinPasses().find(passType))
        for (const auto& p : type->params)
            if (p.name == param) return &p;
    return nullptr;
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

void Settings::setInput(const std::string& target, std::string source) {
    std::erase_if(inputs, [&](const auto& s) { return s.first == target; });
    inputs.emplace_back(target, std::move(source));
}

void Settings::merge(const Settings& more) {
    for (const auto& [name, value] : more.cvars.items()) setCvar(name, value);
    for (const auto& [target, value] : more.sets) setParam(target, value);
    for (const auto& [target, source] : more.inputs) setInput(target, source);
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
    nlohmann::json rebound = nlohmann::json::object();
    for (const auto& [target, source] : inputs) rebound[target] = source;
    return {{"cvars", cvars}, {"set", set}, {"inputs", rebound}};
}

std::string Settings::cvarWhere(const std::string& name) const {
    return fmt::format(fmt::runtime(cvarOrigin), name);
}

std::string Settings::setWhere(const std::string& target) const {
    return fmt::format(fmt::runtime(setOrigin), target);
}

std::string Settings::inputWhere(const std::string& target) const {
    return fmt::format(fmt::runtime(inputOrigin), target);
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

void Settings::setInputText(const std::string& text) {
    auto [target, source] = splitAssignment(text, "--input");
    setInput(target, source);
}

namespace {
// The text of an .ini file as UTF-8. Unreal on Windows saves .ini files in UTF-8 with a
// byte-order mark or in UTF-16 (little-endian, usually with a mark); a UTF-16 file without a
// mark is recognised by its zero high bytes, as every ASCII key has them.
std::string iniText(const std::string& bytes) {
    const auto byte = [&](std::size_t i) { return (unsigned char)bytes[i]; };
    if (bytes.size() >= 3 && byte(0) == 0xEF && byte(1) == 0xBB && byte(2) == 0xBF)
        return bytes.substr(3);
    bool littleEndian = true, utf16 = false;
    std::size_t start = 0;
    if (bytes.size() >= 2 && byte(0) == 0xFF && byte(1) == 0xFE) {
        utf16 = true;
        start = 2;
    } else if (bytes.size() >= 2 && byte(0) == 0xFE && byte(1) == 0xFF) {
        utf16 = true;
        littleEndian = false;
        start = 2;
    } else if (bytes.size() >= 2 && byte(0) != 0 && byte(1) == 0) {
        utf16 = true;
    } else if (bytes.size() >= 2 && byte(0) == 0 && byte(1) != 0) {
        utf16 = true;
        littleEndian = false;
    }
    if (!utf16) return bytes;
    std::string out;
    auto unit = [&](std::size_t i) -> unsigned {
        return littleEndian ? byte(i) | (unsigned(byte(i + 1)) << 8)
                            : (unsigned(byte(i)) << 8) | byte(i + 1);
    };
    for (std::size_t i = start; i + 1 < bytes.size(); i += 2) {
        unsigned c = unit(i);
        if (c >= 0xD800 && c < 0xDC00 && i + 3 < bytes.size()) {  // a surrogate pair
            const unsigned low = unit(i + 2);
            if (low >= 0xDC00 && low < 0xE000) {
                c = 0x10000 + ((c - 0xD800) << 10) + (low - 0xDC00);
                i += 2;
            }
        }
        if (c < 0x80) {
            out += char(c);
        } else if (c < 0x800) {
            out += char(0xC0 | (c >> 6));
            out += char(0x80 | (c & 0x3F));
        } else if (c < 0x10000) {
            out += char(0xE0 | (c >> 12));
            out += char(0x80 | ((c >> 6) & 0x3F));
            out += char(0x80 | (c & 0x3F));
        } else {
            out += char(0xF0 | (c >> 18));
            out += char(0x80 | ((c >> 12) & 0x3F));
            out += char(0x80 | ((c >> 6) & 0x3F));
            out += char(0x80 | (c & 0x3F));
        }
    }
    return out;
}
}  // namespace

Settings readCvarsFile(const std::string& path, bool strict) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw UsageError(fmt::format("--cvars {}: cannot read the file", path));
    std::istringstream in(iniText(std::string(std::istreambuf_iterator<char>(file), {})));
    // Unreal's .ini: cvars under [SystemSettings] or [ConsoleVariables] (what `tune` prints),
    // "; comments", NAME=VALUE lines. Keys of other sections are not cvars and are skipped.
    Settings out;
    std::string line, section;
    std::map<std::string, int> skipped;  // section → lines skipped
    for (int number = 1; std::getline(in, line); ++number) {
        const std::string t = trimmed(line);
        if (t.empty() || t[0] == ';' || t[0] == '#') continue;
        if (t.front() == '[') {
            if (t.back() != ']')
                throw UsageError(fmt::format("--cvars {}:{}: '{}' is not a [Section]", path,
                                             number, t));
            section = t.substr(1, t.size() - 2);
            continue;
        }
        if (section != "SystemSettings" && section != "ConsoleVariables") {
            ++skipped[section.empty() ? "(before any section)" : "[" + section + "]"];
            continue;
        }
        const auto eq = t.find('=');
        if (eq == std::string::npos || eq == 0)
            throw UsageError(fmt::format("--cvars {}:{}: expected NAME=VALUE, got '{}'", path,
                                         number, t));
        out.setCvar(trimmed(t.substr(0, eq)), Settings::valueFromText(trimmed(t.substr(eq + 1))));
    }
    for (const auto& [where, lines] : skipped)
        logWarning(fmt::format("--cvars {}: {} line{} of {} skipped: cvars are read from "
                               "[SystemSettings] and [ConsoleVariables]",
                               path, lines, lines == 1 ? "" : "s", where));
    if (out.cvars.empty()) {
        const std::string why = fmt::format(
            "--cvars {}: 0 cvars read (no NAME=VALUE line under [SystemSettings] or "
            "[ConsoleVariables])",
            path);
        if (strict) throw UsageError(why + "; --strict makes this an error");
        logWarning(why);
    }
    return out;
}

}  // namespace fp::app
