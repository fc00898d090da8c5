#pragma once
// A profile maps a capture file's channels onto the semantic buffers of DESIGN §2 — a table, not
// a code path. `canonical` is framepass's own naming (what `framepass capture` writes); other
// engines' profiles (Unreal MRQ, buffer-visualisation dumps, Blender) are more tables of the
// same shape. A config can also write one inline.
#include "io/ExrReader.h"

#include <nlohmann/json.hpp>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace fp::io {

class CaptureProfile {
public:
    /// Built-in profile by name; throws fp::UsageError (with a did-you-mean) for unknown names.
    static CaptureProfile byName(const std::string& name);
    /// From a config's "profile" value: a name, or {"base": NAME, "buffers": {Buffer: [channels]}}.
    static CaptureProfile fromJson(const nlohmann::json& j, const std::string& where);
    static std::vector<std::string> builtinNames();

    const std::string& name() const { return mName; }
    /// The file channels holding `buffer` (a semantic buffer or Truth.<Name>), `channels` wide.
    std::vector<std::string> channelsFor(const std::string& buffer, int channels) const;
    /// Every buffer whose channels are all present in the file.
    std::set<std::string> availableBuffers(const ExrReader& file) const;
    /// Channel count of every Truth.* layer of the file.
    static std::map<std::string, int> truthChannels(const ExrReader& file);
    /// Which buffer a file channel belongs to ("" when none): for `framepass inspect`.
    std::string bufferOfChannel(const std::string& channel) const;

private:
    std::string mName;
    std::map<std::string, std::vector<std::string>> mOverrides;  // buffer → explicit channels
};

}  // namespace fp::io
