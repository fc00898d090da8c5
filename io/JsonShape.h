#pragma once
// The shape of a JSON document framepass reads (a config, a scene, a camera sidecar), declared
// once: the keys each object may hold, what each holds, its range or choices and its doc. The
// readers check unknown keys against it (with a did-you-mean), `framepass schema` writes it as a
// JSON Schema (draft 2020-12) that editors validate and complete with, and docs/schema/ holds
// those files (the docs test checks they match). Values are then read by the readers, which say
// what is wrong with one in the reader's own words.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace fp::io {

struct JsonObjectShape;

/// What a key holds.
enum class JsonKind {
    Any,
    String,
    Number,
    Integer,
    Bool,
    Vec3,          //!< [x, y, z]
    Object,        //!< an object of the fields of `object`
    ObjectArray,   //!< an array of objects of the fields of `object` (or of `alternative`)
    ObjectMap,     //!< an object whose every value is an object of the fields of `object`
    StringMap,     //!< an object whose every value is a string (port → source, file → source)
    ValueMap,      //!< an object of free keys (cvar → value)
    StringOrList,  //!< a string or an array of strings
    StringOrObject,  //!< a name or an inline object
    IntegerOrString,
};

struct JsonField {
    std::string name;
    JsonKind kind = JsonKind::Any;
    std::string doc;
    std::optional<double> min{}, max{};
    std::vector<std::string> choices{};
    const JsonObjectShape* object = nullptr;  //!< Object, ObjectArray, ObjectMap, StringOrObject
    const JsonObjectShape* alternative = nullptr;  //!< ObjectArray: items may be either shape
    bool required = false;
};

struct JsonObjectShape {
    std::string title;
    std::string doc;
    std::vector<JsonField> fields;

    /// The keys it allows, in declaration order.
    std::vector<std::string> keys() const;
    /// The keys of `j` that it does not allow, each with a did-you-mean suggestion ("" when none
    /// is close).
    std::vector<std::pair<std::string, std::string>> unknownKeys(const nlohmann::json& j) const;
    /// The document as a JSON Schema (draft 2020-12), nested objects included.
    nlohmann::json jsonSchema() const;
};

/// The documents framepass reads (ConfigLoader.cpp and scene/SceneLoader.cpp declare them).
const JsonObjectShape& configShape();
const JsonObjectShape& sceneShape();
/// "config" or "scene" → its shape; fp::UsageError for another name.
const JsonObjectShape& documentShape(const std::string& name);

}  // namespace fp::io
