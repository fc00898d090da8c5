#include "app/TruthDefinitions.h"

#include "app/Settings.h"
#include "framework/PassRegistry.h"
#include "framework/Planner.h"

#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>

namespace fp::app {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr const char* kRadius = "radius";
constexpr const char* kBounces = "bounces";

// ---- The declared tables ---------------------------------------------------------------------

// What defines each truth layer. A recorded quantity comes from the capture's settings (the
// header says what it was); a fixed one is the layer's by name. Layers of one family measure the
// same light but for the quantity: one stands in for another where the quantity matches.
struct TruthLayerDefinition {
    const char* layer;
    const char* family;
    const char* quantity;
    bool recorded;
    double fixed;                // the value when not recorded
    const char* captureOption;   // the `capture` option that sets it (radius: in metres), or null
};
constexpr TruthLayerDefinition kTruthLayers[] = {
    {"Truth.AO", "ao", kRadius, true, 0, "--truth-ao-radius"},
    {"Truth.AOAnyDistance", "ao", kRadius, false, kInf, nullptr},
    {"Truth.DiffuseIndirectOneBounce", "diffuse", kBounces, false, 1, nullptr},
    {"Truth.DiffuseIndirectFull", "diffuse", kBounces, true, 0, nullptr},
    {"Truth.Specular", "specular", kBounces, true, 0, nullptr},
    {"Truth.Combined", "combined", kBounces, true, 0, nullptr},
};

// What a pass output measures, for the truths of the same quantity. `param` sets it (in `unit`:
// metres per the parameter's unit for a radius); a value ≤ 0 of it, or no parameter, is `fixed`.
struct PassOutputDefinition {
    const char* type;
    const char* port;
    const char* quantity;
    const char* param;     // null: fixed by the pass
    double unit;           // metres per parameter unit (radius), 1 (bounces)
    const char* unitName;  // how the parameter's unit is written after its value
    double fixed;
};
constexpr PassOutputDefinition kPassOutputs[] = {
    // Unreal's RTAO, RTGI's AO and the oracle's: occluders within a radius.
    {"rt_ambient_occlusion", "ao", kRadius, "radius", 0.01, " cm", 0},
    {"rt_global_illumination", "ao", kRadius, "aoRadius", 0.01, " cm", 0},
    {"screen_space_oracle", "aoWithinRadius", kRadius, "aoRadius", 1.0, " m", 0},
    // 1 − the fraction of rays that hit, however far the hit.
    {"ssgi", "ao", kRadius, nullptr, 1.0, "", kInf},
    {"hybrid", "ao", kRadius, nullptr, 1.0, "", kInf},
    {"screen_space_oracle", "ao", kRadius, nullptr, 1.0, "", kInf},
    // Diffuse indirect light: SSGI gathers last frame's lit colour, one bounce.
    {"ssgi", "diffuse", kBounces, nullptr, 1.0, "", 1},
    {"screen_space_oracle", "diffuse", kBounces, nullptr, 1.0, "", 1},
    {"rt_global_illumination", "diffuse", kBounces, "maxBounces", 1.0, "", 1},
};

// Passes whose output has its input's definition (denoisers): output port ← the input port of
// the same name.
struct PassThrough {
    const char* type;
    const char* port;
};
constexpr PassThrough kPassThroughs[] = {
    {"ao_denoise", "ao"},      {"ssgi_denoise", "ao"}, {"ssgi_denoise", "diffuse"},
    {"gi_denoise", "ao"},      {"gi_denoise", "diffuse"},
};

// Whether two values of a quantity define the same thing. Bounces: one bounce, or several (a
// path tracer's 256 and a pass's 3 estimate the same light, the pass with the bias of the
// bounces it leaves out, which the error breakdown takes apart); radius: equal.
bool sameValue(const std::string& quantity, double a, double b) {
    if (quantity == kBounces) return (a <= 1) == (b <= 1);
    if (std::isinf(a) || std::isinf(b)) return a == b;
    return std::abs(a - b) <= 1e-6 * std::max(std::abs(a), std::abs(b));
}

// ---- Words -----------------------------------------------------------------------------------

std::string number(double v) { return fmt::format("{:.6g}", v); }

// What a value means, as "… counts occluders within 1 m".
std::string meaning(const std::string& quantity, double v) {
    if (quantity == kRadius)
        return std::isinf(v) ? "counts occluders at any distance"
                             : fmt::format("counts occluders within {} m", number(v));
    if (quantity == kBounces)
        return v <= 1 ? "gathers one bounce" : fmt::format("follows {} bounces", number(v));
    return fmt::format("has {} {}", quantity, number(v));
}

std::string headerName(const std::string& layer, const std::string& quantity) {
    // "Truth.AO" → "framepass:truth.AO.radius"
    return "framepass:truth" + layer.substr(std::string("Truth").size()) + "." + quantity;
}

const TruthLayerDefinition* truthLayer(const std::string& layer) {
    for (const auto& t : kTruthLayers)
        if (layer == t.layer) return &t;
    return nullptr;
}

const PassOutputDefinition* passOutput(const std::string& type, const std::string& port,
                                       const std::string& quantity) {
    for (const auto& p : kPassOutputs)
        if (type == p.type && port == p.port && quantity == p.quantity) return &p;
    return nullptr;
}

// Whether `a` and `b` are truth layers of one family (Truth.AO and Truth.AOAnyDistance).
bool sameFamily(const std::string& a, const std::string& b) {
    const TruthLayerDefinition *ta = truthLayer(a), *tb = truthLayer(b);
    return ta && tb && std::string(ta->family) == tb->family;
}

bool passesThrough(const std::string& type, const std::string& port) {
    for (const auto& p : kPassThroughs)
        if (type == p.type && port == p.port) return true;
    return false;
}

// A pass output found upstream of a measure's source, with the denoisers between.
struct Definer {
    const PlanStep* step = nullptr;
    const PassOutputDefinition* def = nullptr;
    std::vector<std::string> through;  // the pass-through steps, nearest the measure first
};

std::optional<Definer> findDefiner(const Plan& plan, const SourceRef& source,
                                   const std::string& quantity) {
    Definer d;
    const SourceRef* ref = &source;
    for (std::size_t hops = 0; hops <= plan.steps.size(); ++hops) {
        if (ref->fromCapture || ref->step < 0 || ref->step >= int(plan.steps.size()))
            return std::nullopt;
        const PlanStep& step = plan.steps[std::size_t(ref->step)];
        if (const auto* def = passOutput(step.type, ref->port, quantity)) {
            d.step = &step;
            d.def = def;
            return d;
        }
        if (!passesThrough(step.type, ref->port)) return std::nullopt;
        const auto in = step.inputs.find(ref->port);
        if (in == step.inputs.end()) return std::nullopt;
        d.through.push_back(step.name);
        ref = &in->second;
    }
    return std::nullopt;
}

bool isDefault(const PlanStep& step, const std::string& param) {
    const ParamInfo* p = builtinParam(step.type, param);
    return p && step.params.contains(param) && p->defaultValue == step.params.at(param);
}

std::string cvarOf(const PlanStep& step, const std::string& param) {
    const ParamInfo* p = builtinParam(step.type, param);
    return p && !p->cvars.empty() ? p->cvars.front() : "";
}

}  // namespace

std::map<std::string, std::string> truthDefinitionAttributes(double aoRadius, int maxBounces) {
    std::map<std::string, std::string> out;
    for (const auto& t : kTruthLayers) {
        const std::string quantity = t.quantity;
        const double v = !t.recorded            ? t.fixed
                         : quantity == kRadius  ? aoRadius
                                                : double(maxBounces);
        out[headerName(t.layer, quantity)] = std::isinf(v) ? "inf" : number(v);
    }
    return out;
}

TruthDefinitions readTruthDefinitions(const Imf::Header& header) {
    TruthDefinitions out;
    const auto* unitsAttr =
        header.findTypedAttribute<Imf::DoubleAttribute>("framepass:sceneUnitsPerMeter");
    const double units = unitsAttr && unitsAttr->value() > 0 ? unitsAttr->value() : 100.0;
    auto parse = [](const std::string& s) -> std::optional<double> {
        if (s == "inf") return kInf;
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (end == s.c_str() || *end != '\0' || std::isnan(v)) return std::nullopt;
        return v;
    };
    bool any = false;
    for (const auto& t : kTruthLayers) {
        const auto* a = header.findTypedAttribute<Imf::StringAttribute>(headerName(t.layer, t.quantity));
        if (!a) continue;
        if (const auto v = parse(a->value())) {
            out[t.layer][t.quantity] = std::string(t.quantity) == kRadius ? *v / units : *v;
            any = true;
        }
    }
    // Captures made before the attributes above recorded the AO radius alone.
    if (!out.count("Truth.AO"))
        if (const auto* a = header.findTypedAttribute<Imf::StringAttribute>("framepass:truthAoRadius"))
            if (const auto v = parse(a->value())) {
                out["Truth.AO"][kRadius] = *v / units;
                any = true;
            }
    if (any)
        for (const auto& t : kTruthLayers)
            if (!t.recorded && !out[t.layer].count(t.quantity)) out[t.layer][t.quantity] = t.fixed;
    return out;
}

std::vector<Diagnostic> truthDefinitionWarnings(const Plan& plan, const TruthDefinitions& truths) {
    std::vector<Diagnostic> out;
    for (const PlanStep& measure : plan.steps) {
        if (!measure.io.roles.measuresError) continue;
        const auto ref = measure.inputs.find("reference");
        const auto src = measure.inputs.find("source");
        if (ref == measure.inputs.end() || src == measure.inputs.end() || !ref->second.fromCapture)
            continue;
        const std::string& layer = ref->second.buffer;
        const auto truth = truths.find(layer);
        const TruthLayerDefinition* declared = truthLayer(layer);
        if (truth == truths.end()) continue;
        for (const auto& [quantity, truthValue] : truth->second) {
            const auto definer = findDefiner(plan, src->second, quantity);
            if (!definer) continue;
            const PlanStep& pass = *definer->step;
            const PassOutputDefinition& def = *definer->def;
            double value = def.fixed;
            std::string setting;
            if (def.param && pass.params.contains(def.param) && pass.params.at(def.param).is_number()) {
                const double raw = pass.params.at(def.param).get<double>();
                if (raw > 0) value = raw * def.unit;
                setting = fmt::format(" ({}.{} = {}{}{})", pass.name, def.param, number(raw),
                                      def.unitName, isDefault(pass, def.param) ? ", its default" : "");
            }
            if (sameValue(quantity, value, truthValue)) continue;

            // What would compare like with like: the pass's parameter set to the truth's value,
            // another truth layer of the capture with the pass's definition, or a capture made
            // to the pass's.
            std::vector<std::string> remedies;
            if (def.param) {
                const std::string cvar = cvarOf(pass, def.param);
                const std::string also = cvar.empty() ? "" : fmt::format(" (or cvar {})", cvar);
                if (quantity == kRadius && !std::isinf(truthValue))
                    remedies.push_back(fmt::format("set {}.{}={}{}", pass.name, def.param,
                                                   number(truthValue / def.unit), also));
                else if (quantity == kBounces)
                    remedies.push_back(truthValue <= 1
                                           ? fmt::format("set {}.{}=1{}", pass.name, def.param, also)
                                           : fmt::format("set {}.{} above 1{}", pass.name,
                                                         def.param, also));
            }
            for (const auto& [other, definition] : truths) {
                const auto q = definition.find(quantity);
                if (other != layer && sameFamily(other, layer) && q != definition.end() &&
                    sameValue(quantity, value, q->second))
                    remedies.push_back(fmt::format("judge it against {}", other));
            }
            if (quantity == kRadius && !std::isinf(value)) {
                if (declared && declared->captureOption)
                    remedies.push_back(fmt::format("capture with --truth {} {}",
                                                   declared->captureOption, number(value)));
                else if (remedies.empty())  // Truth.AOAnyDistance: Truth.AO at the pass's radius
                    for (const auto& t : kTruthLayers)
                        if (t.captureOption && quantity == t.quantity && sameFamily(t.layer, layer))
                            remedies.push_back(fmt::format(
                                "judge it against {} of a capture made with --truth {} {}",
                                t.layer, t.captureOption, number(value)));
            }
            std::string through;
            for (const auto& t : definer->through) through += (through.empty() ? " (through " : ", ") + t;
            if (!through.empty()) through += ")";
            std::string truthNote;
            if (declared && declared->captureOption && quantity == kRadius && !std::isinf(truthValue))
                truthNote = fmt::format(" (capture {} {})", declared->captureOption, number(truthValue));
            std::string message = fmt::format(
                "{} judges {}.{}{}, which {}{}, against {}, which {}{}: a truth of another "
                "definition",
                measure.name, pass.name, def.port, through, meaning(quantity, value), setting,
                layer, meaning(quantity, truthValue), truthNote);
            if (!remedies.empty())
                message += fmt::format("; to compare like with like, {}", fmt::join(remedies, ", or "));
            out.push_back({measure.pointer, message});
        }
    }
    return out;
}

std::vector<std::string> truthDefinitionMismatch(const std::string& nameA,
                                                 const std::string& layerA,
                                                 const TruthDefinitions& a,
                                                 const std::string& nameB,
                                                 const std::string& layerB,
                                                 const TruthDefinitions& b) {
    std::vector<std::string> out;
    const auto da = a.find(layerA), db = b.find(layerB);
    // Layers of different families (AO against diffuse light) differ in more than a setting.
    if (da == a.end() || db == b.end() || !sameFamily(layerA, layerB)) return out;
    for (const auto& [quantity, va] : da->second) {
        const auto vb = db->second.find(quantity);
        if (vb == db->second.end() || sameValue(quantity, va, vb->second)) continue;
        std::string remedy;
        for (const auto& [other, definition] : b) {
            const auto q = definition.find(quantity);
            if (other != layerB && sameFamily(other, layerB) && q != definition.end() &&
                sameValue(quantity, va, q->second)) {
                remedy = fmt::format("; {} of B has A's definition", other);
                break;
            }
        }
        out.push_back(fmt::format("{} {} but {} {}: the two were made to measure different "
                                  "things{}",
                                  nameA, meaning(quantity, va), nameB, meaning(quantity, vb->second),
                                  remedy));
    }
    return out;
}

}  // namespace fp::app
