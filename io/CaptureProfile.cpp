#include "io/CaptureProfile.h"

#include "io/JsonFile.h"

#include "io/ConfigLoader.h"
#include "foundation/Error.h"
#include "framework/SemanticBuffers.h"
#include "foundation/Suggest.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

namespace fp::io {

namespace {

namespace fs = std::filesystem;

bool isFile(const std::string& nameOrFile) {
    return nameOrFile.find('/') != std::string::npos ||
           (nameOrFile.size() > 5 && nameOrFile.ends_with(".json"));
}

[[noreturn]] void fail(const std::string& where, const std::string& message) {
    throw UsageError(fmt::format("{}: {}", where, message));
}

std::string quoted(const std::vector<std::string>& names) {
    return fmt::format("{}", fmt::join(names, ", "));
}

// A number or a list of `width` numbers (width 0: any length, for Truth layers), as `width` floats.
std::vector<float> numbers(const nlohmann::json& j, std::size_t width, const std::string& where) {
    std::vector<float> out;
    if (j.is_number()) {
        out.assign(std::max<std::size_t>(width, 1), j.get<float>());
    } else if (j.is_array() && (width == 0 || j.size() == width)) {
        for (const auto& v : j) {
            if (!v.is_number()) fail(where, "expected numbers");
            out.push_back(v.get<float>());
        }
    } else {
        fail(where, width ? fmt::format("expected a number or a list of {}", width)
                          : "expected a number or a list of numbers");
    }
    for (float v : out)
        if (!std::isfinite(v)) fail(where, "must be finite");
    return out;
}

std::vector<std::string> channelList(const nlohmann::json& j, const std::string& buffer,
                                     std::size_t width, const std::string& where) {
    if (!j.is_array() || j.empty()) fail(where, "expected a list of channel names");
    std::vector<std::string> out;
    for (const auto& c : j) {
        if (!c.is_string() || c.get<std::string>().empty()) fail(where, "channel names are strings");
        out.push_back(c.get<std::string>());
    }
    // The check the old assert did, now in every build: a mapping as wide as its buffer.
    if (width && out.size() != width) {
        const SemanticBuffer* b = findSemanticBuffer(buffer);
        fail(where, fmt::format("{} has {} channel{} ({}); this lists {} ({})", buffer, width,
                                width == 1 ? "" : "s", quoted(b->channels), out.size(),
                                quoted(out)));
    }
    return out;
}

const std::set<std::string> kMappingKeys = {"channels", "sum",   "constant",      "previousFrame",
                                            "scale",    "offset", "skyAbove",     "normalEncoding",
                                            "file",     "assumption", "doc", "warning",
                                            "override"};

BufferMapping parseMapping(const nlohmann::json& j, const std::string& buffer, bool multiFile,
                           const std::string& where) {
    if (!j.is_object())
        fail(where, "a buffer mapping is an object with 'channels', 'sum', 'constant' or "
                    "'previousFrame'");
    const SemanticBuffer* sem = findSemanticBuffer(buffer);
    const std::size_t width = sem ? sem->channels.size() : 0;
    BufferMapping m;
    m.pointer = where;
    int sources = 0;
    for (const auto& [key, v] : j.items()) {
        const std::string at = where + "/" + key;
        if (!kMappingKeys.count(key))
            fail(at, fmt::format("unknown key{}; a mapping has {}",
                                 didYouMean(key, std::vector<std::string>(kMappingKeys.begin(),
                                                                          kMappingKeys.end())),
                                 quoted({kMappingKeys.begin(), kMappingKeys.end()})));
        if (key == "channels") {
            m.groups = {channelList(v, buffer, width, at)};
            ++sources;
        } else if (key == "sum") {
            if (!v.is_array() || v.empty()) fail(at, "expected a list of channel lists");
            for (std::size_t i = 0; i < v.size(); ++i) {
                const std::string term = at + "/" + std::to_string(i);
                if (v[i].is_object()) {
                    // {"product": [[..], [..]]}: one term, its channel lists multiplied.
                    if (v[i].size() != 1 || !v[i].contains("product") ||
                        !v[i]["product"].is_array() || v[i]["product"].size() < 2)
                        fail(term, "a term is a channel list or {\"product\": [two or more "
                                   "channel lists]}");
                    const auto& factors = v[i]["product"];
                    for (std::size_t f = 0; f < factors.size(); ++f) {
                        m.groups.push_back(channelList(factors[f], buffer, width,
                                                       term + "/product/" + std::to_string(f)));
                        m.termOf.push_back(int(i));
                    }
                } else {
                    m.groups.push_back(channelList(v[i], buffer, width, term));
                    m.termOf.push_back(int(i));
                }
            }
            for (const auto& g : m.groups)
                if (g.size() != m.groups.front().size())
                    fail(at, "every summed group has the same number of channels");
            ++sources;
        } else if (key == "constant") {
            m.constant = numbers(v, width, at);
            ++sources;
        } else if (key == "previousFrame") {
            if (!v.is_string() || !findSemanticBuffer(v.get<std::string>()))
                fail(at, "expected the name of a buffer of frame N−1");
            m.previousFrame = v.get<std::string>();
            const SemanticBuffer* from = findSemanticBuffer(m.previousFrame);
            if (from->channels.size() != width)
                fail(at, fmt::format("{} has {} channels, {} has {}", m.previousFrame,
                                     from->channels.size(), buffer, width));
            ++sources;
        } else if (key == "scale") {
            m.scale = numbers(v, width, at);
        } else if (key == "offset") {
            m.offset = numbers(v, width, at);
        } else if (key == "skyAbove") {
            if (!isDepthBuffer(buffer))
                fail(at, "only depth buffers have a sky threshold");
            if (!v.is_number() || !(v.get<double>() > 0)) fail(at, "expected a positive number");
            m.skyAbove = v.get<float>();
        } else if (key == "normalEncoding") {
            if (buffer != "WorldNormal") fail(at, "only WorldNormal has a normal encoding");
            const std::string e = v.is_string() ? v.get<std::string>() : "";
            if (e == "signed") m.normals = BufferMapping::Normals::Signed;
            else if (e == "unorm") m.normals = BufferMapping::Normals::Unorm;
            else if (e == "auto") m.normals = BufferMapping::Normals::Auto;
            else fail(at, "expected \"signed\" (-1..1), \"unorm\" (n·0.5+0.5) or \"auto\"");
        } else if (key == "file") {
            if (!multiFile) fail(at, "'file' needs the profile's \"files\" pattern");
            if (!v.is_string() || v.get<std::string>().empty()) fail(at, "expected a file key");
            m.file = v.get<std::string>();
        } else if (key == "override") {
            if (!v.is_object() || v.size() != 2 || !v.contains("where") || !v.contains("value"))
                fail(at, "expected {\"where\": [channels], \"value\": the buffer's value there}");
            m.overrideWhere = channelList(v["where"], buffer, 0, at + "/where");
            if (m.overrideWhere.empty()) fail(at + "/where", "expected one or more channels");
            m.overrideValue = numbers(v["value"], width, at + "/value");
        } else if (key == "assumption" || key == "doc" || key == "warning") {
            if (!v.is_string()) fail(at, "expected text");
            if (key == "assumption") m.assumption = v.get<std::string>();
            if (key == "warning") m.warning = v.get<std::string>();
        }
    }
    if (sources != 1)
        fail(where, "give exactly one of 'channels', 'sum', 'constant' or 'previousFrame'");
    if (multiFile && !m.groups.empty() && m.file.empty())
        fail(where, "this profile reads one file per buffer: say which with 'file'");
    if (!m.groups.empty()) {
        const std::size_t w = m.groups.front().size();
        if (!m.scale.empty() && m.scale.size() != w) m.scale.assign(w, m.scale.front());
        if (!m.offset.empty() && m.offset.size() != w) m.offset.assign(w, m.offset.front());
    }
    return m;
}

nlohmann::json readJsonFile(const std::string& path) {
    return io::readJsonFile(path, "capture profile");
}

std::string builtinPath(const std::string& name) {
    return configDirectory() + "/profiles/" + name + ".json";
}

}  // namespace

std::vector<std::string> CaptureProfile::builtinNames() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(configDirectory() + "/profiles", ec))
        if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

CaptureProfile CaptureProfile::load(const std::string& nameOrFile) {
    if (isFile(nameOrFile)) return parse(readJsonFile(nameOrFile), nameOrFile);
    const auto names = builtinNames();
    if (std::find(names.begin(), names.end(), nameOrFile) == names.end())
        throw UsageError(fmt::format("unknown capture profile '{}'{}; known: [{}] (or give a "
                                     "profile file, NAME.json)",
                                     nameOrFile, didYouMean(nameOrFile, names), quoted(names)));
    const std::string path = builtinPath(nameOrFile);
    return parse(readJsonFile(path), path);
}

CaptureProfile CaptureProfile::parse(const nlohmann::json& j, const std::string& source,
                                     int depth) {
    if (!j.is_object()) fail(source, "a profile is a JSON object");
    CaptureProfile p;
    // "base": start from another profile (a built-in name, or a file beside this one) and
    // replace only what this file says, buffer by buffer.
    if (j.contains("base")) {
        const std::string at = source + ": /base";
        if (!j["base"].is_string()) fail(at, "expected a profile name or file");
        if (depth >= 8) fail(at, "profiles extend each other more than 8 deep (a cycle?)");
        std::string base = j["base"].get<std::string>();
        if (base.ends_with(".json") && fs::path(base).is_relative())
            base = (fs::path(source).parent_path() / base).string();
        p = isFile(base) ? parse(readJsonFile(base), base, depth + 1) : load(base);
        p.mDescription.clear();
    }
    p.mName = fs::path(source).stem().string();
    for (const auto& [key, v] : j.items()) {
        const std::string at = source + ": /" + key;
        if (key == "base") {
            continue;
        } else if (key == "version") {
            if (v != 1) fail(at, "this framepass reads profile version 1");
        } else if (key == "name" || key == "description" || key == "files" || key == "camera") {
            if (!v.is_string()) fail(at, "expected text");
            if (key == "name") p.mName = v.get<std::string>();
            if (key == "description") p.mDescription = v.get<std::string>();
            if (key == "camera") p.mCamera = v.get<std::string>();
            if (key == "files") {
                p.mFilePattern = v.get<std::string>();
                if (p.mFilePattern.find("{base}") == std::string::npos ||
                    p.mFilePattern.find("{file}") == std::string::npos)
                    fail(at, "a file pattern holds {base} and {file}");
            }
        } else if (key == "sceneUnitsPerMeter") {
            if (!v.is_number() || !(v.get<double>() > 0)) fail(at, "expected a positive number");
            p.mSceneUnitsPerMeter = v.get<double>();
        } else if (key == "unmapped") {
            if (!v.is_object()) fail(at, "expected {\"layer\": \"why\"}");
            for (const auto& [layer, why] : v.items())
                p.mUnmapped[layer] = why.is_string() ? why.get<std::string>() : "";
        } else if (key != "buffers") {
            fail(at, "unknown key (a profile has version, base, name, description, "
                     "sceneUnitsPerMeter, files, camera, buffers, unmapped)");
        }
    }
    if (!j.contains("buffers") && !j.contains("base"))
        fail(source, "a profile needs \"buffers\" (or a \"base\" to extend)");
    if (j.contains("buffers")) {
        CaptureProfile own;
        own.mFilePattern = p.mFilePattern;
        own.parseBuffers(j["buffers"], source + ": /buffers");
        for (auto& [buffer, list] : own.mBuffers) p.mBuffers[buffer] = std::move(list);
    }
    p.checkPreviousFrames();
    return p;
}

void CaptureProfile::parseBuffers(const nlohmann::json& j, const std::string& where) {
    if (!j.is_object()) fail(where, "expected {\"Buffer\": mapping or [mappings]}");
    for (const auto& [buffer, v] : j.items()) {
        const std::string at = where + "/" + buffer;
        if (!findSemanticBuffer(buffer) && !isTruthBuffer(buffer)) {
            std::vector<std::string> names;
            for (const auto& b : semanticBuffers()) names.push_back(b.name);
            fail(at, fmt::format("unknown buffer '{}'{}", buffer, didYouMean(buffer, names)));
        }
        std::vector<BufferMapping> list;
        const bool shorthand = v.is_array() && !v.empty() &&
                               std::all_of(v.begin(), v.end(), [](const auto& e) { return e.is_string(); });
        if (shorthand) {  // ["chan", ...] is {"channels": ["chan", ...]}
            list.push_back(parseMapping({{"channels", v}}, buffer, !mFilePattern.empty(), at));
        } else if (v.is_array()) {
            if (v.empty()) fail(at, "expected at least one mapping");
            for (std::size_t i = 0; i < v.size(); ++i)
                list.push_back(
                    parseMapping(v[i], buffer, !mFilePattern.empty(), at + "/" + std::to_string(i)));
        } else {
            list.push_back(parseMapping(v, buffer, !mFilePattern.empty(), at));
        }
        mBuffers[buffer] = std::move(list);
    }
}

void CaptureProfile::checkPreviousFrames() const {
    // Frame N−1's buffer is read from that frame's own channels, never from frame N−2.
    for (const auto& [buffer, list] : mBuffers)
        for (const auto& m : list)
            if (!m.previousFrame.empty())
                if (const auto* from = mappings(m.previousFrame))
                    for (const auto& f : *from)
                        if (!f.previousFrame.empty())
                            fail(m.pointer, fmt::format("{} is itself taken from the previous "
                                                        "frame ({})",
                                                        m.previousFrame, f.pointer));
}

CaptureProfile CaptureProfile::fromJson(const nlohmann::json& j, const std::string& where) {
    if (j.is_string()) return load(j.get<std::string>());
    if (!j.is_object())
        fail(where, "a profile is a name, a profile file, or {\"base\": .., \"buffers\": {..}}");
    for (const auto& [key, v] : j.items())
        if (key != "base" && key != "buffers" && key != "camera" && key != "sceneUnitsPerMeter")
            fail(where + "/" + key, "unknown key (an inline profile has 'base', 'camera', "
                                    "'sceneUnitsPerMeter' and 'buffers')");
    const nlohmann::json base = j.value("base", nlohmann::json("canonical"));
    if (!base.is_string()) fail(where + "/base", "expected a profile name or file");
    CaptureProfile p = load(base.get<std::string>());
    p.mName = p.mName + "+inline";
    if (j.contains("sceneUnitsPerMeter")) {
        const auto& u = j["sceneUnitsPerMeter"];
        if (!u.is_number() || !(u.get<double>() > 0))
            fail(where + "/sceneUnitsPerMeter", "expected a positive number");
        p.mSceneUnitsPerMeter = u.get<double>();
    }
    if (j.contains("camera")) {
        if (!j["camera"].is_string()) fail(where + "/camera", "expected a camera name");
        p.mCamera = j["camera"].get<std::string>();
    }
    if (j.contains("buffers")) {
        // Inline buffers replace the base's one by one.
        CaptureProfile over;
        over.mFilePattern = p.mFilePattern;
        over.parseBuffers(j["buffers"], where + "/buffers");
        for (auto& [buffer, list] : over.mBuffers) p.mBuffers[buffer] = std::move(list);
        p.checkPreviousFrames();
    }
    return p;
}

const std::vector<BufferMapping>* CaptureProfile::mappings(const std::string& buffer) const {
    auto it = mBuffers.find(buffer);
    return it == mBuffers.end() ? nullptr : &it->second;
}

}  // namespace fp::io
