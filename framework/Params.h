#pragma once
// Typed pass parameters (architecture anchors B3): a plain struct with defaults (Filament
// Options.h) plus a spec that binds JSON names to its members. The spec is the single source for
// parsing, validation, `framepass passes` docs and writing resolved values back to the report.
#include "framework/Diagnostics.h"
#include "foundation/Suggest.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace fp {

/// What `framepass passes TYPE` prints about one parameter.
struct ParamInfo {
    std::string name;
    std::string type;  //!< bool, int, float or string
    std::string doc;
    nlohmann::json defaultValue;
    std::optional<double> min, max;
    std::vector<std::string> choices;
    std::vector<std::string> cvars;  //!< Unreal console variables that set it
    bool needsHistory = false;  //!< acts only on a frame with history (a sequence's later frames)
};

template <class T>
class ParamSpec {
public:
    using Member = std::variant<bool T::*, int T::*, float T::*, std::string T::*>;

    /// `member` may be one of a base of T (a pass whose parameters extend another's).
    template <class M, class Base>
        requires std::is_base_of_v<Base, T>
    ParamSpec& add(std::string name, M Base::*member, std::string doc) {
        M T::*m = member;
        // Its reader and writer are made here, for the member types T has, so that no code
        // accesses T through a pointer to a member type it does not have (GCC warns of such code).
        auto read = [m](const T& params) { return asJson(params.*m); };
        auto write = [m](T& params, const Entry& e, const nlohmann::json& v, const std::string& at,
                         Diagnostics& diag) { assign(params.*m, e, v, at, diag); };
        mEntries.push_back({std::move(name), Member(m), std::move(doc), {}, {}, {}, {}, false,
                            std::move(read), std::move(write)});
        return *this;
    }
    /// An Unreal console variable that sets the last added parameter (a config's "cvars" or
    /// --cvar). Declared here, beside the parameter, and nowhere else: the cvar table is made
    /// from these declarations (CvarTable).
    /// The parameter acts only across frames (a temporal blend): on one frame, or the first of
    /// a sequence, every value gives the same pixels (`tune` does not search it there).
    ParamSpec& needsHistory() {
        mEntries.back().needsHistory = true;
        return *this;
    }
    ParamSpec& cvar(std::string name) {
        mEntries.back().cvars.push_back(std::move(name));
        return *this;
    }
    /// Inclusive range for the last added numeric parameter.
    ParamSpec& range(double lo, double hi) {
        mEntries.back().min = lo;
        mEntries.back().max = hi;
        return *this;
    }
    /// Allowed values for the last added string parameter.
    ParamSpec& choices(std::vector<std::string> values) {
        mEntries.back().choices = std::move(values);
        return *this;
    }

    std::vector<std::string> names() const {
        std::vector<std::string> n;
        for (const auto& e : mEntries)
            n.push_back(e.name);
        return n;
    }

    /// Parses `params` (a JSON object) over the defaults of T. Every problem — unknown key (with a
    /// did-you-mean), wrong type, out-of-range value — is added to `diag` under `pointer`.
    T parse(const nlohmann::json& params, const std::string& pointer, Diagnostics& diag) const {
        T out{};
        if (params.is_null())
            return out;
        if (!params.is_object()) {
            diag.error(pointer, "parameters must be a JSON object");
            return out;
        }
        for (const auto& [key, value] : params.items()) {
            const std::string at = pointer + "/" + jsonPointerEscape(key);
            const Entry* e = find(key);
            if (!e) {
                diag.error(at, "unknown parameter '" + key + "'" + didYouMean(key, names()));
                continue;
            }
            e->write(out, *e, value, at, diag);
        }
        return out;
    }

    nlohmann::json toJson(const T& params) const {
        nlohmann::json j = nlohmann::json::object();
        for (const auto& e : mEntries)
            j[e.name] = e.read(params);
        return j;
    }

    std::vector<ParamInfo> infos() const {
        const T defaults{};
        std::vector<ParamInfo> list;
        for (const auto& e : mEntries) {
            ParamInfo info{e.name, "", e.doc, {}, e.min, e.max, e.choices, e.cvars,
                           e.needsHistory};
            info.defaultValue = e.read(defaults);
            info.type = std::visit([](auto member) { return typeName(member); }, e.member);
            list.push_back(std::move(info));
        }
        return list;
    }

private:
    struct Entry {
        std::string name;
        Member member;
        std::string doc;
        std::optional<double> min, max;
        std::vector<std::string> choices;
        std::vector<std::string> cvars;
        bool needsHistory = false;
        std::function<nlohmann::json(const T&)> read;  //!< the member's value in a T
        /// Sets the member of a T from a JSON value, checked as `assign` checks it.
        std::function<void(T&, const Entry&, const nlohmann::json&, const std::string&,
                           Diagnostics&)>
            write;
    };

    const Entry* find(const std::string& key) const {
        for (const auto& e : mEntries)
            if (e.name == key)
                return &e;
        return nullptr;
    }

    static const char* typeName(bool T::*) { return "bool"; }
    static const char* typeName(int T::*) { return "int"; }
    static const char* typeName(float T::*) { return "float"; }
    static const char* typeName(std::string T::*) { return "string"; }

    static void checkRange(double v, const Entry& e, const std::string& at, Diagnostics& diag) {
        if ((e.min && v < *e.min) || (e.max && v > *e.max))
            diag.error(at, fmt::format("{} is out of range [{}, {}] for '{}'", v,
                                       e.min ? fmt::format("{}", *e.min) : "-inf",
                                       e.max ? fmt::format("{}", *e.max) : "inf", e.name));
    }

    // A float parameter as the shortest decimal that reads back as it (0.88, not the double
    // 0.8799999952316284 that 0.88f widens to): what a user typed, in every listing and report.
    static nlohmann::json asJson(float v) { return std::strtod(fmt::format("{}", v).c_str(), nullptr); }
    template <class V>
    static nlohmann::json asJson(const V& v) {
        return v;
    }

    static void assign(bool& dst,
                       const Entry& e,
                       const nlohmann::json& v,
                       const std::string& at,
                       Diagnostics& diag) {
        // Unreal cvars are often written 0/1; accept those for booleans as the console does.
        if (v.is_boolean())
            dst = v.get<bool>();
        else if (v.is_number_integer() && (v.get<long long>() == 0 || v.get<long long>() == 1))
            dst = v.get<long long>() == 1;
        else
            diag.error(at, fmt::format("'{}' must be a boolean, got {}", e.name, v.dump()));
    }
    static void assign(int& dst,
                       const Entry& e,
                       const nlohmann::json& v,
                       const std::string& at,
                       Diagnostics& diag) {
        if (!v.is_number_integer()) {
            diag.error(at, fmt::format("'{}' must be an integer, got {}", e.name, v.dump()));
            return;
        }
        checkRange(double(v.get<long long>()), e, at, diag);
        dst = int(v.get<long long>());
    }
    static void assign(float& dst,
                       const Entry& e,
                       const nlohmann::json& v,
                       const std::string& at,
                       Diagnostics& diag) {
        if (!v.is_number()) {
            diag.error(at, fmt::format("'{}' must be a number, got {}", e.name, v.dump()));
            return;
        }
        checkRange(v.get<double>(), e, at, diag);
        dst = v.get<float>();
    }
    static void assign(std::string& dst,
                       const Entry& e,
                       const nlohmann::json& v,
                       const std::string& at,
                       Diagnostics& diag) {
        if (!v.is_string()) {
            diag.error(at, fmt::format("'{}' must be a string, got {}", e.name, v.dump()));
            return;
        }
        dst = v.get<std::string>();
        if (!e.choices.empty() &&
            std::find(e.choices.begin(), e.choices.end(), dst) == e.choices.end())
            diag.error(at,
                       fmt::format("'{}' is not one of [{}] for '{}'{}", dst,
                                   fmt::join(e.choices, ", "), e.name, didYouMean(dst, e.choices)));
    }

    std::vector<Entry> mEntries;
};

}  // namespace fp
