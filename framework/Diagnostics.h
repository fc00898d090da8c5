#pragma once
// Config and plan problems are collected, not thrown one at a time (Falcor validateGraph, pbrt
// ErrorExitDeferred): a user fixes every mistake of a config in one round.
#include <string>
#include <vector>

namespace fp {

struct Diagnostic {
    std::string pointer;  //!< JSON pointer into the config (RFC 6901), e.g. /passes/2/params/quality
    std::string message;
};

class Diagnostics {
public:
    void error(std::string pointer, std::string message);
    void warning(std::string pointer, std::string message);
    bool hasErrors() const { return !mErrors.empty(); }
    const std::vector<Diagnostic>& errors() const { return mErrors; }
    const std::vector<Diagnostic>& warnings() const { return mWarnings; }
    /// Throws fp::UsageError listing every error ("<source>: <pointer>: <message>") if any.
    void throwIfErrors(const std::string& source) const;
    /// "pointer: message" lines.
    static std::string format(const std::vector<Diagnostic>& list, const std::string& source);

private:
    std::vector<Diagnostic> mErrors, mWarnings;
};

/// Escapes a key for use in a JSON pointer (RFC 6901: ~ → ~0, / → ~1).
std::string jsonPointerEscape(const std::string& key);

}  // namespace fp
