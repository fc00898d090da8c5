#pragma once
// Unreal console variables, accepted verbatim in a config's "cvars" section and mapped onto pass
// parameters (docs/config.md, cvars: names and defaults from Unreal's code, not its help strings).
// The table is computed: each parameter declares the cvars that set it beside its own declaration
// (ParamSpec::cvar), and the registry adds one short list of cvars framepass recognises but does
// not emulate. A recognised-but-not-emulated cvar set to anything but the value framepass runs is
// a warning that names it; an unknown one too.
#include "framework/PassRegistry.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace fp {

struct CvarMapping {
    std::string cvar;      //!< Unreal name, e.g. r.SSGI.LeakFreeReprojection
    std::string passType;  //!< pass type the value is for ("" = recognised but not emulated)
    std::string param;     //!< that pass's parameter
    std::string note;      //!< shown by `framepass passes` and in warnings
    nlohmann::json emulatedValue;  //!< for a cvar that sets nothing: the value framepass runs
};

class CvarTable {
public:
    explicit CvarTable(const PassRegistry& registry);
    /// The first mapping of `cvar` (a cvar may set parameters of several pass types).
    const CvarMapping* find(const std::string& cvar) const;
    /// The mapping of `cvar` onto pass type `passType`, if it has one.
    const CvarMapping* find(const std::string& cvar, const std::string& passType) const;
    /// Every pass type `cvar` sets a parameter of.
    std::vector<std::string> targets(const std::string& cvar) const;
    const std::vector<CvarMapping>& all() const { return mEntries; }
    std::vector<std::string> names() const;
    /// The table's spelling of `cvar`, matched without regard to case as Unreal's console does
    /// (r.ssgi.quality is r.SSGI.Quality); `cvar` itself when the table does not know it.
    std::string spelling(const std::string& cvar) const;

private:
    std::vector<CvarMapping> mEntries;
};

}  // namespace fp
