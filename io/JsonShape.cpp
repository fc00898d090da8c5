#include "io/JsonShape.h"

#include "foundation/Error.h"
#include "foundation/Suggest.h"

#include <algorithm>

namespace fp::io {

std::vector<std::string> JsonObjectShape::keys() const {
    std::vector<std::string> k;
    for (const auto& f : fields)
        k.push_back(f.name);
    return k;
}

std::vector<std::pair<std::string, std::string>> JsonObjectShape::unknownKeys(
    const nlohmann::json& j) const {
    std::vector<std::pair<std::string, std::string>> unknown;
    if (!j.is_object())
        return unknown;
    const std::vector<std::string> allowed = keys();
    for (const auto& [k, v] : j.items())
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
            unknown.emplace_back(k, didYouMean(k, allowed));
    return unknown;
}

namespace {

nlohmann::json objectSchema(const JsonObjectShape& shape);

nlohmann::json fieldSchema(const JsonField& f) {
    nlohmann::json s;
    const nlohmann::json number = {{"type", "number"}};
    switch (f.kind) {
    case JsonKind::Any: break;
    case JsonKind::String: s["type"] = "string"; break;
    case JsonKind::Number: s["type"] = "number"; break;
    case JsonKind::Integer: s["type"] = "integer"; break;
    case JsonKind::Bool: s["type"] = "boolean"; break;
    case JsonKind::Vec3:
        s = {{"type", "array"}, {"items", number}, {"minItems", 3}, {"maxItems", 3}};
        break;
    case JsonKind::Object: s = objectSchema(*f.object); break;
    case JsonKind::ObjectArray:
        s = {{"type", "array"},
             {"items", f.alternative ? nlohmann::json{{"oneOf",
                                                      {objectSchema(*f.object),
                                                       objectSchema(*f.alternative)}}}
                                     : objectSchema(*f.object)}};
        break;
    case JsonKind::ObjectMap:
        s = {{"type", "object"}, {"additionalProperties", objectSchema(*f.object)}};
        break;
    case JsonKind::StringMap:
        s = {{"type", "object"}, {"additionalProperties", {{"type", "string"}}}};
        break;
    case JsonKind::ValueMap: s = {{"type", "object"}}; break;
    case JsonKind::StringOrList:
        s["oneOf"] = {{{"type", "string"}},
                      {{"type", "array"}, {"items", {{"type", "string"}}}, {"minItems", 1}}};
        break;
    case JsonKind::StringOrObject:
        s["oneOf"] = {{{"type", "string"}}, f.object ? objectSchema(*f.object) : nlohmann::json{{"type", "object"}}};
        break;
    case JsonKind::IntegerOrString: s["type"] = {"integer", "string"}; break;
    }
    if (f.min) s["minimum"] = *f.min;
    if (f.max) s["maximum"] = *f.max;
    if (!f.choices.empty()) s["enum"] = f.choices;
    if (!f.doc.empty()) s["description"] = f.doc;
    return s;
}

nlohmann::json objectSchema(const JsonObjectShape& shape) {
    nlohmann::json s = {{"type", "object"}, {"additionalProperties", false}};
    if (!shape.title.empty()) s["title"] = shape.title;
    if (!shape.doc.empty()) s["description"] = shape.doc;
    nlohmann::json properties = nlohmann::json::object(), required = nlohmann::json::array();
    for (const auto& f : shape.fields) {
        properties[f.name] = fieldSchema(f);
        if (f.required) required.push_back(f.name);
    }
    s["properties"] = properties;
    if (!required.empty()) s["required"] = required;
    return s;
}

}  // namespace

const JsonObjectShape& documentShape(const std::string& name) {
    if (name == "config") return configShape();
    if (name == "scene") return sceneShape();
    throw UsageError(fmt::format("no document '{}'{}; known: config, scene", name,
                                 didYouMean(name, {"config", "scene"})));
}

nlohmann::json JsonObjectShape::jsonSchema() const {
    nlohmann::json s = objectSchema(*this);
    s["$schema"] = "https://json-schema.org/draft/2020-12/schema";
    return s;
}

}  // namespace fp::io
