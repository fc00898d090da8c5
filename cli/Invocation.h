#pragma once
// What the whole process was asked for: framepass's version, the command line, the thread count
// and how much to say on stderr (-q / -v). main.cpp sets it once after parsing; the commands read
// it for their messages and `run --report` records it.
//
// Streams: a command's result (its table, or its JSON with --json) is the only thing on stdout;
// progress, information and warnings go to stderr (none of them with -q), per-pass timing lines
// too with -v. Errors always go to stderr.
#include <string>
#include <vector>

namespace fp::cli {

enum class Verbosity { Quiet, Normal, Verbose };

struct Invocation {
    std::string version;                 //!< "0.1.0"
    std::vector<std::string> arguments;  //!< argv, the program included
    int threadsRequested = 0;            //!< --threads as given (0 = all cores)
    int threads = 0;                     //!< worker threads actually used
    Verbosity verbosity = Verbosity::Normal;
    /// The arguments joined by spaces, those with spaces or quotes quoted for a shell.
    std::string commandLine() const;
};

const Invocation& invocation();
void setInvocation(Invocation invocation);

/// "Progress: NN%" on stderr (Deadline's progress syntax), except with -q.
void logProgress(int percent);
/// A line of information on stderr, except with -q.
void logInfo(const std::string& line);
/// "warning: <line>" on stderr, except with -q.
void logWarning(const std::string& line);
/// A line on stderr only with -v.
void logVerbose(const std::string& line);

/// For commands that can stop cleanly (run): SIGTERM and SIGINT no longer end the process at
/// once; the first is recorded and the command stops at its next safe point (between passes),
/// where throwIfStopped throws fp::Interrupted. A second signal ends the process at once.
void catchStopSignals();
/// The signal that asked the process to stop (SIGTERM, SIGINT), or 0.
int stopSignal();
/// Throws fp::Interrupted ("stopped by SIGTERM …") when a stop signal arrived.
void throwIfStopped();

}  // namespace fp::cli
