#include "framework/Diagnostics.h"

#include "foundation/Error.h"

namespace fp {

void Diagnostics::error(std::string pointer, std::string message) {
    mErrors.push_back({std::move(pointer), std::move(message)});
}

void Diagnostics::warning(std::string pointer, std::string message) {
    mWarnings.push_back({std::move(pointer), std::move(message)});
}

std::string Diagnostics::format(const std::vector<Diagnostic>& list, const std::string& source) {
    std::string out;
    for (const auto& d : list) {
        out += source.empty() ? "" : source + ": ";
        out += (d.pointer.empty() ? std::string("/") : d.pointer) + ": " + d.message + "\n";
    }
    return out;
}

void Diagnostics::throwIfErrors(const std::string& source) const {
    if (mErrors.empty()) return;
    std::vector<ConfigProblem> problems;
    for (const auto& d : mErrors) problems.push_back({d.pointer, d.message});
    throw UsageError(fmt::format("{} error{} in the configuration:\n{}", mErrors.size(),
                                 mErrors.size() == 1 ? "" : "s", format(mErrors, source)),
                     source, std::move(problems));
}

std::string jsonPointerEscape(const std::string& key) {
    std::string out;
    for (char c : key) {
        if (c == '~') out += "~0";
        else if (c == '/') out += "~1";
        else out += c;
    }
    return out;
}

}  // namespace fp
