#include "cli/Invocation.h"

#include <iostream>

namespace fp::cli {

namespace {
Invocation gInvocation;

std::string shellQuoted(const std::string& arg) {
    if (!arg.empty() && arg.find_first_of(" \t\n'\"\\$`*?[]{}()<>|&;#~") == std::string::npos)
        return arg;
    std::string out = "'";
    for (char c : arg)
        out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}
}  // namespace

std::string Invocation::commandLine() const {
    std::string line;
    for (const auto& a : arguments)
        line += (line.empty() ? "" : " ") + shellQuoted(a);
    return line;
}

const Invocation& invocation() {
    return gInvocation;
}

void setInvocation(Invocation invocation) {
    gInvocation = std::move(invocation);
}

void logProgress(int percent) {
    if (gInvocation.verbosity != Verbosity::Quiet)
        std::cerr << "Progress: " << percent << "%\n" << std::flush;
}

void logInfo(const std::string& line) {
    if (gInvocation.verbosity != Verbosity::Quiet)
        std::cerr << line << "\n" << std::flush;
}

void logWarning(const std::string& line) {
    if (gInvocation.verbosity != Verbosity::Quiet)
        std::cerr << "warning: " << line << "\n" << std::flush;
}

void logVerbose(const std::string& line) {
    if (gInvocation.verbosity == Verbosity::Verbose)
        std::cerr << line << "\n" << std::flush;
}

}  // namespace fp::cli
