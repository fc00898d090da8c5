#pragma once
// A profile maps a capture's files and channels onto the semantic buffers of docs/captures.md. Profiles
// are data: configs/profiles/<name>.json (canonical, ue-mrq, ue-bufvis, blender), a user's JSON
// file, or an object inline in a config that overrides a base profile buffer by buffer. No
// engine has a code path of its own; what a profile can say is the BufferMapping below.
#include <nlohmann/json.hpp>

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace fp::io {

/// One way to fill a buffer. A buffer lists one or more; the first whose files and channels the
/// capture has wins.
struct BufferMapping {
    enum class Normals { Signed, Unorm, Auto };

    /// Channel groups, each exactly as wide as the buffer and in its order (the swizzle); more
    /// than one group is summed ("sum"). May contain {camera} (see CaptureProfile::camera()).
    std::vector<std::vector<std::string>> groups;
    /// The term each group belongs to: groups of one term multiply, terms add ("sum" with
    /// {"product": [...]} elements: Blender's light passes are light × colour). Empty = each
    /// group its own term.
    std::vector<int> termOf;
    std::vector<float> constant;  //!< non-empty: the buffer is this value everywhere
    /// "override": pixels where any of these channels is > 0 take `overrideValue` instead
    /// (Blender's emitters: ShadingModel 0, unlit, where the Emit pass is non-zero). The
    /// mapping is usable only when the capture has these channels too.
    std::vector<std::string> overrideWhere;
    std::vector<float> overrideValue;
    std::vector<float> scale, offset;  //!< per channel: v·scale + offset (sign flips included)
    float skyAbove = std::numeric_limits<float>::infinity();  //!< depth ≥ this (raw) is sky
    Normals normals = Normals::Signed;  //!< Unorm: n = 2v − 1; Auto: whichever is unit length
    std::string file;           //!< multi-file profiles: the {file} of the file holding it
    std::string previousFrame;  //!< this buffer is that buffer of frame N−1 of the sequence
    std::string assumption;     //!< a guess the user should know about: a warning when used
    std::string warning;        //!< a caveat of this source (not a guess): said once when read
    std::string pointer;        //!< where it was written ("profiles/x.json: /buffers/Y/1")
};

class CaptureProfile {
public:
    /// A built-in profile (configs/profiles/<name>.json) or a profile file (a path ending in
    /// .json). Throws fp::UsageError naming the file and JSON pointer of any mistake, with a
    /// did-you-mean for unknown names.
    static CaptureProfile load(const std::string& nameOrFile);
    /// A config's "profile": a name, a file, or {"base": NAME|FILE, "camera": .., "buffers": {..}}
    /// whose buffers replace the base's. `where` prefixes error locations.
    static CaptureProfile fromJson(const nlohmann::json& j, const std::string& where);
    static std::vector<std::string> builtinNames();

    const std::string& name() const { return mName; }
    const std::string& description() const { return mDescription; }
    /// Scene units per metre the profile's buffers are in (Unreal: 100), when it says.
    std::optional<double> sceneUnitsPerMeter() const { return mSceneUnitsPerMeter; }
    /// "" for single-file captures, else the file pattern with {base} and {file}.
    const std::string& filePattern() const { return mFilePattern; }
    /// The camera whose layers to read where channel names hold {camera} ("" = the only one).
    const std::string& camera() const { return mCamera; }

    /// The ways the profile fills `buffer`, in order; nullptr when it does not map it.
    const std::vector<BufferMapping>* mappings(const std::string& buffer) const;
    const std::map<std::string, std::vector<BufferMapping>>& buffers() const { return mBuffers; }
    /// What the profile says it leaves out on purpose, layer → why (for `inspect`).
    const std::map<std::string, std::string>& unmapped() const { return mUnmapped; }

private:
    static CaptureProfile parse(const nlohmann::json& j, const std::string& source, int depth = 0);
    void parseBuffers(const nlohmann::json& j, const std::string& where);
    void checkPreviousFrames() const;
    std::string mName, mDescription, mFilePattern, mCamera;
    std::optional<double> mSceneUnitsPerMeter;
    std::map<std::string, std::vector<BufferMapping>> mBuffers;
    std::map<std::string, std::string> mUnmapped;
};

}  // namespace fp::io
