#include "io/ConfigLoader.h"

#include "io/JsonFile.h"
#include "io/JsonShape.h"

#include "framework/Diagnostics.h"
#include "foundation/Error.h"
#include "foundation/Suggest.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <fstream>

namespace fp::io {

namespace fs = std::filesystem;

namespace {

// The shape of a config (JsonShape.h): the keys each object may hold, with their docs. Unknown
// keys are checked against it; `framepass schema config` writes it as a JSON Schema.
using K = JsonKind;
const JsonObjectShape kPassShape = {
    "pass", "a pass of the chain",
    {{"name", K::String, "its name in the chain (default: its type); ports are NAME.port"},
     {"type", K::String, "its pass type (framepass passes lists them)", {}, {}, {}, nullptr, nullptr, true},
     {"params", K::ValueMap, "parameters by name (framepass passes TYPE lists them)"},
     {"inputs", K::StringMap, "port → source: 'capture:Buffer' or 'pass.port'"},
     {"description", K::String, "ignored"}}};
const JsonObjectShape kLightTemplateShape = {
    "forEachLight", "passes repeated for each light of the scene, named <pass>_<light>",
    {{"passes", K::ObjectArray, "the passes of one light; {light} in a value is the light's name",
      {}, {}, {}, &kPassShape, nullptr, true},
     {"colorIn", K::String, "the input port that receives the previous light's colour"},
     {"colorOut", K::String, "the output port that carries this light's colour on"},
     {"rewire", K::StringMap, "pass.port → source, rebound to the last light's output"},
     {"outputs", K::ValueMap, "per-light outputs: file → source(s), {light} in names"},
     {"description", K::String, "ignored"}}};
const JsonObjectShape kTemplateEntryShape = {
    "template entry", "a light template in the chain",
    {{"forEachLight", K::Object, "the template", {}, {}, {}, &kLightTemplateShape, nullptr, true},
     {"description", K::String, "ignored"}}};
const JsonObjectShape kColorShape = {
    "color", "colour management of previews",
    {{"ocioConfig", K::String, "OCIO config for previews; default $OCIO, then configs/ocio/config.ocio"}}};
const JsonObjectShape kExrShape = {
    "exr", "how EXR outputs are written",
    {{"compression", K::String, "lossless codecs only: lossy ones damage data layers", {}, {},
      {"zip", "zips", "piz", "none"}},
     {"colorPrecision", K::String, "how colour layers of outputs and dumps are stored (data layers are always float32)",
      {}, {}, {"half", "float"}}}};

const JsonObjectShape kPngShape = {
    "png", "how PNG previews are written",
    {{"compressionLevel", K::Integer,
      "zlib's level, 0 (stored) to 9 (smallest); the pixels are the same at every level",
      0, 9}}};

const std::vector<std::string> kEngines = {"ue4.27", "ue5", "ue4.27-raytracing",
                                           "framepass-hybrid"};

nlohmann::json readJsonFile(const std::string& path) {
    return io::readJsonFile(path, "config");
}

std::string resolvePath(const std::string& baseDir, const std::string& p) {
    if (p.empty() || fs::path(p).is_absolute() || baseDir.empty())
        return p;
    return (fs::path(baseDir) / p).lexically_normal().string();
}

void checkKeys(const nlohmann::json& obj,
               const JsonObjectShape& shape,
               const std::string& pointer,
               const std::string& what,
               Diagnostics& diag) {
    for (const auto& [k, suggestion] : shape.unknownKeys(obj))
        diag.error(pointer + "/" + jsonPointerEscape(k),
                   fmt::format("unknown {} key '{}'{}", what, k, suggestion));
}

std::string stringAt(const nlohmann::json& j,
                     const char* key,
                     const std::string& pointer,
                     Diagnostics& diag) {
    if (!j.contains(key))
        return "";
    if (!j[key].is_string()) {
        diag.error(pointer + "/" + key, fmt::format("'{}' must be a string", key));
        return "";
    }
    return j[key].get<std::string>();
}

NodeDesc parsePass(const nlohmann::json& p, const std::string& ptr, Diagnostics& diag) {
    checkKeys(p, kPassShape, ptr, "pass", diag);
    NodeDesc n;
    n.pointer = ptr;
    n.type = stringAt(p, "type", ptr, diag);
    if (!p.contains("type"))
        diag.error(ptr, "missing 'type'");
    n.name = p.contains("name") ? stringAt(p, "name", ptr, diag) : n.type;
    if (p.contains("params")) {
        if (p["params"].is_object())
            n.params = p["params"];
        else
            diag.error(ptr + "/params", "'params' must be an object");
    }
    if (p.contains("inputs")) {
        if (!p["inputs"].is_object()) {
            diag.error(ptr + "/inputs", "'inputs' must be an object of port → source");
        } else {
            for (const auto& [port, src] : p["inputs"].items()) {
                if (src.is_string())
                    n.inputs[port] = src.get<std::string>();
                else
                    diag.error(ptr + "/inputs/" + jsonPointerEscape(port),
                               "a source must be a string ('capture:Buffer' or 'pass.port')");
            }
        }
    }
    return n;
}

std::vector<OutputDesc> parseOutputs(const nlohmann::json& outputs,
                                     const std::string& pointer,
                                     Diagnostics& diag) {
    std::vector<OutputDesc> list;
    if (!outputs.is_object()) {
        diag.error(pointer, "'outputs' must be an object of file → source(s)");
        return list;
    }
    for (const auto& [file, src] : outputs.items()) {
        const std::string ptr = pointer + "/" + jsonPointerEscape(file);
        OutputDesc o;
        o.file = file;
        o.pointer = ptr;
        if (src.is_string()) {
            o.sources.push_back(src.get<std::string>());
        } else if (src.is_array() && !src.empty()) {
            for (const auto& s : src)
                if (s.is_string())
                    o.sources.push_back(s.get<std::string>());
                else
                    diag.error(ptr, "sources must be strings");
        } else {
            diag.error(ptr, "an output names a source ('pass.port') or a list of them");
            continue;
        }
        const bool png = fs::path(file).extension() == ".png";
        if (!png && fs::path(file).extension() != ".exr")
            diag.error(ptr, fmt::format("'{}' must end in .exr or .png", file));
        if (png && o.sources.size() != 1)
            diag.error(ptr, "a .png output shows exactly one source");
        list.push_back(std::move(o));
    }
    return list;
}

// {"forEachLight": {...}}: passes repeated per light, inserted where the entry stands.
LightTemplate parseLightTemplate(const nlohmann::json& t,
                                 const std::string& ptr,
                                 std::size_t position,
                                 Diagnostics& diag) {
    LightTemplate lt;
    lt.pointer = ptr;
    lt.position = position;
    if (!t.is_object()) {
        diag.error(ptr, "'forEachLight' must be an object");
        return lt;
    }
    checkKeys(t, kLightTemplateShape, ptr, "forEachLight", diag);
    if (!t.contains("passes") || !t["passes"].is_array())
        diag.error(ptr + "/passes", "'passes' must be an array of passes");
    else
        for (std::size_t k = 0; k < t["passes"].size(); ++k) {
            const std::string at = ptr + "/passes/" + std::to_string(k);
            if (t["passes"][k].is_object())
                lt.passes.push_back(parsePass(t["passes"][k], at, diag));
            else
                diag.error(at, "a pass must be an object with at least 'type'");
        }
    lt.colorIn = stringAt(t, "colorIn", ptr, diag);
    lt.colorOut = stringAt(t, "colorOut", ptr, diag);
    if (t.contains("rewire")) {
        if (!t["rewire"].is_object())
            diag.error(ptr + "/rewire", "'rewire' must be an object");
        else
            for (const auto& [target, src] : t["rewire"].items())
                if (src.is_string())
                    lt.rewire[target] = src.get<std::string>();
                else
                    diag.error(ptr + "/rewire/" + jsonPointerEscape(target),
                               "a source must be a string");
    }
    if (t.contains("outputs"))
        lt.outputs = parseOutputs(t["outputs"], ptr + "/outputs", diag);
    return lt;
}

void parsePasses(const nlohmann::json& passes,
                 const std::string& pointer,
                 GraphDesc& g,
                 Diagnostics& diag) {
    if (!passes.is_array()) {
        diag.error(pointer, "'passes' must be an array of {\"type\": ...} objects");
        return;
    }
    for (std::size_t i = 0; i < passes.size(); ++i) {
        const std::string ptr = pointer + "/" + std::to_string(i);
        const auto& p = passes[i];
        if (!p.is_object()) {
            diag.error(ptr, "a pass must be an object with at least 'type'");
        } else if (p.contains("forEachLight")) {
            checkKeys(p, kTemplateEntryShape, ptr, "template", diag);
            g.lightTemplates.push_back(
                parseLightTemplate(p["forEachLight"], ptr + "/forEachLight", g.nodes.size(), diag));
        } else {
            g.nodes.push_back(parsePass(p, ptr, diag));
        }
    }
}

}  // namespace

const JsonObjectShape& configShape() {
    static const JsonObjectShape shape = {
        "framepass config",
        "A chain of Unreal's lighting passes on a capture (docs/config.md).",
        {{"version", K::Integer, "1", 1, 1, {}, nullptr, nullptr, true},
         {"engine", K::String, "a config without passes runs configs/<engine>.json", {}, {},
          kEngines},
         {"device", K::String, "where the passes with a CUDA kernel run (--device)", {}, {},
          {"cpu", "cuda"}},
         {"capture", K::String, "capture EXR or frame pattern (####, %04d, @@@, shot.1-10#.exr)"},
         {"frames", K::IntegerOrString, "frame spec, oiiotool syntax: 1001, 1-10, 1-10x2, 3,4,10-20x2"},
         {"profile", K::StringOrObject, "capture profile: a built-in name, a FILE.json, or inline {\"base\": ...}"},
         {"previous", K::String, "the previous frame's capture, for one capture that is not a sequence"},
         {"camera", K::String, "camera sidecar JSON (pattern allowed)"},
         {"scene", K::String, "scene JSON: its lights expand the light templates, its meshes are read when a pass traces rays"},
         {"cvars", K::ValueMap, "Unreal console variables by their exact names"},
         {"set", K::ValueMap, "pass parameters as PASS.PARAM → value, applied as --set is (after the passes' params)"},
         {"inputs", K::StringMap, "PASS.INPUT → source ('pass.port' or 'capture:Buffer'), rebinding that input as --input does"},
         {"passes", K::ObjectArray, "the chain", {}, {}, {}, &kPassShape, &kTemplateEntryShape},
         {"outputs", K::ValueMap, "file → 'pass.port' or a list of them (.exr), or one source (.png)"},
         {"color", K::Object, "colour management of previews", {}, {}, {}, &kColorShape},
         {"exr", K::Object, "how EXR outputs are written", {}, {}, {}, &kExrShape},
         {"png", K::Object, "how PNG previews are written", {}, {}, {}, &kPngShape},
         {"description", K::String, "ignored"},
         {"$schema", K::String, "ignored: the JSON Schema an editor validates with"}}};
    return shape;
}

std::string configDirectory() {
    if (const char* env = std::getenv("FRAMEPASS_CONFIG_DIR"); env && *env)
        return env;
    // A build finds the source tree's configs/; an installed framepass (cmake --install) the
    // copy beside it, <prefix>/share/framepass/configs, once the source tree is gone.
    if (fs::is_directory(FP_CONFIG_DIR)) return FP_CONFIG_DIR;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    const fs::path installed = exe.parent_path().parent_path() / "share/framepass/configs";
    return !ec && fs::is_directory(installed) ? installed.string() : FP_CONFIG_DIR;
}

nlohmann::json parseCliValue(const std::string& text) {
    try {
        return parseJsonLimited(text, fmt::format("'{}'", text.substr(0, 40)));
    } catch (const UsageError& e) {
        // Text that is not JSON is a string; JSON too deep to trust is an error.
        if (std::string(e.what()).find("nested more than") != std::string::npos)
            throw;
        return text;
    }
}

RunConfig parseRunConfig(const nlohmann::json& j,
                         const std::string& source,
                         const std::string& baseDir) {
    Diagnostics diag;
    RunConfig rc;
    rc.path = source;
    rc.baseDir = baseDir;
    if (!j.is_object())
        throw UsageError(fmt::format("{}: the config must be a JSON object", source));
    checkKeys(j, configShape(), "", "config", diag);
    if (!j.contains("version"))
        diag.error("/version", "missing 'version' (use 1)");
    else if (j["version"] != 1)
        diag.error("/version", "only version 1 is understood");
    rc.graph.engine = j.contains("engine") ? stringAt(j, "engine", "", diag) : "ue4.27";
    rc.graph.device = j.contains("device") ? stringAt(j, "device", "", diag) : "cpu";
    if (rc.graph.device != "cpu" && rc.graph.device != "cuda")
        diag.error("/device", fmt::format("unknown device '{}'; known: cpu, cuda", rc.graph.device));
    if (std::find(kEngines.begin(), kEngines.end(), rc.graph.engine) == kEngines.end())
        diag.error("/engine", fmt::format("unknown engine '{}'{}; known: {}",
                                          rc.graph.engine, didYouMean(rc.graph.engine, kEngines),
                                          fmt::join(kEngines, ", ")));
    rc.capture = resolvePath(baseDir, stringAt(j, "capture", "", diag));
    rc.camera = resolvePath(baseDir, stringAt(j, "camera", "", diag));
    rc.previous = resolvePath(baseDir, stringAt(j, "previous", "", diag));
    rc.scene = resolvePath(baseDir, stringAt(j, "scene", "", diag));
    if (j.contains("frames")) {
        if (j["frames"].is_number_integer())
            rc.frames = j["frames"].dump();  // range-checked with the spec (parseFrameSpec)
        else if (j["frames"].is_number())    // at once: the frames are needed before planning
            throw UsageError(
                fmt::format("{}: /frames: {} is not a frame number (an integer) or "
                            "a frame spec",
                            source, j["frames"].dump()));
        else
            rc.frames = stringAt(j, "frames", "", diag);
    }
    if (j.contains("profile")) {
        // A profile file (NAME.json) resolves against the config's folder, like every path in
        // a config; a built-in profile name stays a name.
        rc.profile = j["profile"];
        auto resolveProfile = [&](nlohmann::json& v) {
            if (v.is_string() && v.get<std::string>().ends_with(".json"))
                v = resolvePath(baseDir, v.get<std::string>());
        };
        resolveProfile(rc.profile);
        if (rc.profile.is_object() && rc.profile.contains("base"))
            resolveProfile(rc.profile["base"]);
    }
    if (j.contains("color")) {
        if (!j["color"].is_object())
            diag.error("/color", "'color' must be an object");
        else {
            checkKeys(j["color"], kColorShape, "/color", "color", diag);
            rc.ocioConfig =
                resolvePath(baseDir, stringAt(j["color"], "ocioConfig", "/color", diag));
        }
    }
    if (j.contains("exr")) {
        if (!j["exr"].is_object())
            diag.error("/exr", "'exr' must be an object");
        else {
            checkKeys(j["exr"], kExrShape, "/exr", "exr", diag);
            if (j["exr"].contains("compression"))
                rc.compression = stringAt(j["exr"], "compression", "/exr", diag);
            if (j["exr"].contains("colorPrecision")) {
                rc.colorPrecision = stringAt(j["exr"], "colorPrecision", "/exr", diag);
                if (rc.colorPrecision != "half" && rc.colorPrecision != "float")
                    diag.error("/exr/colorPrecision",
                               fmt::format("'{}': expected \"half\" or \"float\"",
                                           rc.colorPrecision));
            }
        }
    }
    if (j.contains("png")) {
        if (!j["png"].is_object())
            diag.error("/png", "'png' must be an object");
        else {
            checkKeys(j["png"], kPngShape, "/png", "png", diag);
            if (j["png"].contains("compressionLevel")) {
                const auto& v = j["png"]["compressionLevel"];
                if (!v.is_number_integer() || v.get<int>() < 0 || v.get<int>() > 9)
                    diag.error("/png/compressionLevel",
                               fmt::format("{}: expected an integer from 0 to 9", v.dump()));
                else
                    rc.pngLevel = v.get<int>();
            }
        }
    }
    if (j.contains("cvars")) {
        if (j["cvars"].is_object())
            rc.graph.cvars = j["cvars"];
        else
            diag.error("/cvars", "'cvars' must be an object of Unreal console variables");
    }
    if (j.contains("set")) {
        if (j["set"].is_object())
            rc.graph.sets = j["set"];
        else
            diag.error("/set", "'set' must be an object of PASS.PARAM → value");
    }
    if (j.contains("inputs") && j["inputs"].is_object())  // the shape check says what else is wrong
        rc.graph.inputs = j["inputs"];
    if (j.contains("passes")) {
        parsePasses(j["passes"], "/passes", rc.graph, diag);
        if (j.contains("outputs"))
            rc.graph.outputs = parseOutputs(j["outputs"], "/outputs", diag);
    } else if (!diag.hasErrors()) {
        // No chain of its own: the engine's preset supplies passes and outputs.
        const std::string preset =
            (fs::path(configDirectory()) / (rc.graph.engine + ".json")).string();
        const nlohmann::json pj = readJsonFile(preset);
        rc.preset = preset;
        const std::string presetPointer = "(preset " + rc.graph.engine + ")";
        Diagnostics presetDiag;
        parsePasses(pj.at("passes"), presetPointer + "/passes", rc.graph, presetDiag);
        if (j.contains("outputs")) {
            rc.graph.outputs = parseOutputs(j["outputs"], "/outputs", diag);
            // The user's outputs replace the preset's, the light step's files included.
            for (auto& t : rc.graph.lightTemplates)
                t.outputs.clear();
        } else {
            rc.graph.outputs =
                parseOutputs(pj.at("outputs"), presetPointer + "/outputs", presetDiag);
        }
        presetDiag.throwIfErrors(preset);
        // The preset's cvars are the engine's defaults; the user's own cvars win.
        if (pj.contains("cvars")) {
            nlohmann::json merged = pj["cvars"];
            for (const auto& [k, v] : rc.graph.cvars.items())
                merged[k] = v;
            rc.graph.cvars = merged;
        }
    }
    rc.errors = diag.errors();
    return rc;
}

RunConfig loadRunConfig(const std::string& path) {
    if (path == "-") {
        // "-" is the standard input, read once (bench and tune plan it many times); its paths
        // resolve against the working directory.
        static const std::string text(std::istreambuf_iterator<char>(std::cin), {});
        return parseRunConfig(parseJsonLimited(text, "- (standard input)"), "-", "");
    }
    const nlohmann::json j = readJsonFile(path);
    return parseRunConfig(j, path, fs::path(path).parent_path().string());
}

}  // namespace fp::io
