#include "cli/Invocation.h"

#include "passes/core/Error.h"

#include <csignal>
#include <cstring>
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

namespace {
volatile std::sig_atomic_t gStopSignal = 0;

extern "C" void onStopSignal(int signal) {
    if (gStopSignal != 0) {  // asked twice: stop now
        std::signal(signal, SIG_DFL);
        std::raise(signal);
    }
    gStopSignal = signal;
}
}  // namespace

void catchStopSignals() {
    std::signal(SIGTERM, onStopSignal);
    std::signal(SIGINT, onStopSignal);
}

int stopSignal() { return gStopSignal; }

void throwIfStopped() {
    if (const int s = gStopSignal)
        throw Interrupted(s, fmt::format("stopped by {} at a safe point",
                                         s == SIGTERM ? "SIGTERM" : s == SIGINT ? "SIGINT"
                                                                                : sigabbrev_np(s)));
}

void logVerbose(const std::string& line) {
    if (gInvocation.verbosity == Verbosity::Verbose)
        std::cerr << line << "\n" << std::flush;
}

}  // namespace fp::cli
