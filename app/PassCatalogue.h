#pragma once
// The pass catalogue: every pass type's ports, parameters and cvars as JSON, made from the same
// specs that validate configs (`framepass passes --json`, the Python module's passes()), and the
// pass reference docs/passes.md is (`framepass passes --markdown`).
#include "framework/PassRegistry.h"

#include <nlohmann/json.hpp>

#include <string>

namespace fp::app {

/// One pass type: {"type", "doc", "inputs", "outputs", "params", "cvars", "needsScene", ...}.
nlohmann::json describePassType(const PassType& type);
/// The same by id; fp::UsageError (with a suggestion) for an unknown one.
nlohmann::json describePassType(const std::string& id);
/// Every built-in pass type, in registration order.
nlohmann::json passCatalogue();
/// The catalogue (or part of it) as the Markdown pass reference.
std::string passReferenceMarkdown(const nlohmann::json& types);

/// Every cvar framepass knows (CvarTable: the parameters' declarations plus the recognised,
/// not emulated ones), in name order: {"cvar", "emulated", "sets": [{"pass", "param", "type",
/// "default", "min", "max", "choices", "doc"}]} for an emulated one, {"cvar", "emulated": false,
/// "value" (the value framepass runs as; null: none), "note"} for the others
/// (`framepass passes --cvars --json`).
nlohmann::json cvarCatalogue();
/// The cvar table of docs/config.md (`framepass passes --cvars --markdown`).
std::string cvarReferenceMarkdown(const nlohmann::json& cvars);
/// The cvars of cvarCatalogue() that set a parameter of pass type `type`.
nlohmann::json cvarsOfPass(const nlohmann::json& cvars, const std::string& type);

/// `passes`' table: each type and its doc; `detailed`, its ports, parameters and cvars too.
std::string passReferenceText(const nlohmann::json& types, bool detailed);
/// `passes --cvars`' table: each cvar and what it sets (or why it is not emulated).
std::string cvarReferenceText(const nlohmann::json& cvars);

}  // namespace fp::app
