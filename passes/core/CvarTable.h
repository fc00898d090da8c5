#pragma once
// Unreal console variables, accepted verbatim in a config's "cvars" section and mapped onto pass
// parameters (users_and_conventions §5: names and defaults from Unreal's code, not help strings).
// A cvar framepass knows but does not emulate is a warning that names it; an unknown one too.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace fp {

struct CvarMapping {
    std::string cvar;       //!< Unreal name, e.g. r.SSGI.LeakFreeReprojection
    std::string passType;   //!< pass type the value is for ("" = recognised but not emulated)
    std::string param;      //!< that pass's parameter
    std::string note;       //!< shown by `framepass passes` and in warnings
    nlohmann::json emulatedValue;  //!< for a cvar that sets nothing: the value framepass runs
};

class CvarTable {
public:
    CvarTable();
    /// The first mapping of `cvar` (a cvar may set parameters of several pass types).
    const CvarMapping* find(const std::string& cvar) const;
    /// The mapping of `cvar` onto pass type `passType`, if it has one.
    const CvarMapping* find(const std::string& cvar, const std::string& passType) const;
    /// Whether any mapping of `cvar` targets one of `passTypes`.
    template <class Pred>
    bool anyTarget(const std::string& cvar, Pred&& isPresent) const {
        for (const auto& e : mEntries)
            if (e.cvar == cvar && isPresent(e.passType)) return true;
        return false;
    }
    const std::vector<CvarMapping>& all() const { return mEntries; }
    std::vector<std::string> names() const;

private:
    std::vector<CvarMapping> mEntries;
};

}  // namespace fp
