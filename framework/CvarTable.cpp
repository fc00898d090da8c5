#include "framework/CvarTable.h"

#include "foundation/Suggest.h"

#include <algorithm>

namespace fp {

CvarTable::CvarTable(const PassRegistry& registry) {
    for (const auto& type : registry.types())
        for (const auto& param : type.params)
            for (const auto& cvar : param.cvars)
                mEntries.push_back({cvar, type.id, param.name, param.doc, {}});
    for (const auto& r : registry.recognisedCvars())
        mEntries.push_back({r.cvar, "", "", r.note, r.emulatedValue});
}

const CvarMapping* CvarTable::find(const std::string& cvar) const {
    for (const auto& e : mEntries)
        if (e.cvar == cvar)
            return &e;
    return nullptr;
}

std::string CvarTable::spelling(const std::string& cvar) const {
    const std::string key = asciiLowercase(cvar);
    for (const auto& e : mEntries)
        if (asciiLowercase(e.cvar) == key) return e.cvar;
    return cvar;
}

const CvarMapping* CvarTable::find(const std::string& cvar, const std::string& passType) const {
    for (const auto& e : mEntries)
        if (e.cvar == cvar && e.passType == passType)
            return &e;
    return nullptr;
}

std::vector<std::string> CvarTable::targets(const std::string& cvar) const {
    std::vector<std::string> types;
    for (const auto& e : mEntries)
        if (e.cvar == cvar && !e.passType.empty())
            types.push_back(e.passType);
    return types;
}

std::vector<std::string> CvarTable::names() const {
    std::vector<std::string> n;
    for (const auto& e : mEntries)
        if (std::find(n.begin(), n.end(), e.cvar) == n.end())
            n.push_back(e.cvar);
    return n;
}

}  // namespace fp
