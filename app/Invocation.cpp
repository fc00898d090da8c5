#include "app/Invocation.h"

#include "foundation/Error.h"

#include <atomic>
#include <csignal>
#include <cstring>
#include <iostream>
#include <mutex>

namespace fp::app {

namespace {
Invocation gInvocation;
std::mutex gLogMutex;
LogHandler gLogHandler;
// Lock-free, so a signal handler may set it.
std::atomic<int> gStopSignal{0};
static_assert(std::atomic<int>::is_always_lock_free);

std::string shellQuoted(const std::string& arg) {
    if (!arg.empty() && arg.find_first_of(" \t\n'\"\\$`*?[]{}()<>|&;#~") == std::string::npos)
        return arg;
    std::string out = "'";
    for (char c : arg)
        out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

void log(LogKind kind, const std::string& text) {
    const Verbosity v = gInvocation.verbosity;
    if (v == Verbosity::Quiet || (kind == LogKind::Verbose && v != Verbosity::Verbose))
        return;
    // The handler is called outside the lock: a door's handler may wait for something (Python's
    // GIL) that a thread waiting for this lock holds.
    LogHandler handler;
    {
        std::lock_guard<std::mutex> lock(gLogMutex);
        handler = gLogHandler;
    }
    if (handler) {
        handler(kind, text);
        return;
    }
    std::lock_guard<std::mutex> lock(gLogMutex);
    switch (kind) {
    case LogKind::Progress: std::cerr << "Progress: " << text << "%\n"; break;
    case LogKind::Warning: std::cerr << "warning: " << text << "\n"; break;
    default: std::cerr << text << "\n";
    }
    std::cerr << std::flush;
}
}  // namespace

std::string Invocation::commandLine() const {
    std::string line;
    for (const auto& a : arguments) {
        if (!line.empty()) line += ' ';
        line += shellQuoted(a);
    }
    return line;
}

const Invocation& invocation() { return gInvocation; }
void setInvocation(Invocation invocation) { gInvocation = std::move(invocation); }

void setLogHandler(LogHandler handler) {
    std::lock_guard<std::mutex> lock(gLogMutex);
    gLogHandler = std::move(handler);
}

void logProgress(int percent) { log(LogKind::Progress, std::to_string(percent)); }
void logInfo(const std::string& line) { log(LogKind::Info, line); }
void logWarning(const std::string& line) { log(LogKind::Warning, line); }
void logVerbose(const std::string& line) { log(LogKind::Verbose, line); }

void requestStop(int signal) { gStopSignal.store(signal); }
int stopSignal() { return gStopSignal.load(); }

void throwIfStopped() {
    if (const int s = gStopSignal.load())
        throw Interrupted(s, fmt::format("stopped by {} at a safe point",
                                         s == SIGTERM ? "SIGTERM" : s == SIGINT ? "SIGINT"
                                                                                : sigabbrev_np(s)));
}

}  // namespace fp::app
