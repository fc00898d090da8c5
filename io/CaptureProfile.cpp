#include "io/CaptureProfile.h"

#include "passes/core/Error.h"
#include "passes/core/SemanticBuffers.h"
#include "passes/core/Suggest.h"

namespace fp::io {

namespace {
// Truth layers carry colour as R G B and scalars as Y (DESIGN §2).
std::vector<std::string> truthSuffixes(int channels) {
    if (channels == 1) return {"Y"};
    if (channels == 4) return {"R", "G", "B", "A"};
    return {"R", "G", "B"};
}
}  // namespace

std::vector<std::string> CaptureProfile::builtinNames() { return {"canonical"}; }

CaptureProfile CaptureProfile::byName(const std::string& name) {
    if (name != "canonical")
        throw UsageError(fmt::format("unknown capture profile '{}'{}; known: [{}]", name,
                                     didYouMean(name, builtinNames()),
                                     fmt::join(builtinNames(), ", ")));
    CaptureProfile p;
    p.mName = name;
    return p;
}

CaptureProfile CaptureProfile::fromJson(const nlohmann::json& j, const std::string& where) {
    if (j.is_string()) return byName(j.get<std::string>());
    if (!j.is_object())
        throw UsageError(fmt::format("{}: a profile is a name or an object", where));
    CaptureProfile p = byName(j.value("base", "canonical"));
    p.mName = "inline";
    for (const auto& [key, v] : j.items()) {
        if (key == "base") continue;
        if (key != "buffers")
            throw UsageError(fmt::format("{}/{}: unknown key (a profile has 'base' and 'buffers')",
                                         where, key));
        if (!v.is_object())
            throw UsageError(fmt::format("{}/buffers: expected {{\"Buffer\": [channels]}}", where));
        for (const auto& [buffer, chans] : v.items()) {
            const std::string at = where + "/buffers/" + buffer;
            if (!findSemanticBuffer(buffer) && !isTruthBuffer(buffer)) {
                std::vector<std::string> names;
                for (const auto& b : semanticBuffers()) names.push_back(b.name);
                throw UsageError(fmt::format("{}: unknown buffer '{}'{}", at, buffer,
                                             didYouMean(buffer, names)));
            }
            if (!chans.is_array())
                throw UsageError(fmt::format("{}: expected a list of channel names", at));
            std::vector<std::string> list;
            for (const auto& c : chans) list.push_back(c.get<std::string>());
            p.mOverrides[buffer] = list;
        }
    }
    return p;
}

std::vector<std::string> CaptureProfile::channelsFor(const std::string& buffer, int channels) const {
    if (auto it = mOverrides.find(buffer); it != mOverrides.end()) return it->second;
    std::vector<std::string> suffixes;
    if (const SemanticBuffer* b = findSemanticBuffer(buffer)) suffixes = b->channels;
    else suffixes = truthSuffixes(channels);
    std::vector<std::string> names;
    for (const auto& s : suffixes) names.push_back(buffer + "." + s);
    return names;
}

std::set<std::string> CaptureProfile::availableBuffers(const ExrReader& file) const {
    std::set<std::string> out;
    auto allPresent = [&](const std::vector<std::string>& names) {
        for (const auto& n : names)
            if (!file.findChannel(n)) return false;
        return !names.empty();
    };
    for (const auto& b : semanticBuffers())
        if (allPresent(channelsFor(b.name, int(b.channels.size())))) out.insert(b.name);
    // Truth layers: "Truth.<Name>.<C>", where <Name> itself may contain dots (Truth.Shadow.Key).
    for (const auto& c : file.channels()) {
        if (!isTruthBuffer(c.name)) continue;
        const auto dot = c.name.rfind('.');
        const std::string layer = c.name.substr(0, dot);
        out.insert(layer);
    }
    for (const auto& [buffer, names] : mOverrides)
        if (allPresent(names)) out.insert(buffer);
    return out;
}

std::map<std::string, int> CaptureProfile::truthChannels(const ExrReader& file) {
    std::map<std::string, std::set<std::string>> suffixes;
    for (const auto& c : file.channels()) {
        if (!isTruthBuffer(c.name)) continue;
        const auto dot = c.name.rfind('.');
        suffixes[c.name.substr(0, dot)].insert(c.name.substr(dot + 1));
    }
    std::map<std::string, int> out;
    for (const auto& [layer, s] : suffixes) out[layer] = int(s.size());
    return out;
}

std::string CaptureProfile::bufferOfChannel(const std::string& channel) const {
    for (const auto& [buffer, names] : mOverrides)
        for (const auto& n : names)
            if (n == channel) return buffer;
    const auto dot = channel.rfind('.');
    if (dot == std::string::npos) return "";
    const std::string layer = channel.substr(0, dot);
    if (findSemanticBuffer(layer) || isTruthBuffer(layer)) return layer;
    return "";
}

}  // namespace fp::io
