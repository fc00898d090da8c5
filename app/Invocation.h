#pragma once
// What the whole process was asked for, and where the application's messages go.
//
// The invocation (framepass's version, the command line, the thread count, how much to say) is
// set once by the door that drives the library (the CLI after parsing its options); `run
// --report` records it. Messages: progress, information and warnings go through one handler,
// stderr by default (none of them when quiet), per-pass timing lines only when verbose. A door
// that is not a terminal (the Python module, the server) sets its own handler.
//
// Stopping: a door asks the application to stop (a signal, a cancelled request) with
// requestStop; the application stops at its next safe point (between passes), where
// throwIfStopped throws fp::Interrupted.
#include <functional>
#include <string>
#include <vector>

namespace fp::app {

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

enum class LogKind { Progress, Info, Warning, Verbose };
/// Receives every message the verbosity lets through ("NN" for progress, the line otherwise).
using LogHandler = std::function<void(LogKind, const std::string&)>;
/// Replaces the handler (an empty one restores stderr).
void setLogHandler(LogHandler handler);

/// "Progress: NN%" on stderr (Deadline's progress syntax), except when quiet.
void logProgress(int percent);
/// A line of information on stderr, except when quiet.
void logInfo(const std::string& line);
/// "warning: <line>" on stderr, except when quiet.
void logWarning(const std::string& line);
/// A line on stderr only when verbose.
void logVerbose(const std::string& line);

/// Asks the process's work to stop at its next safe point; `signal` names why (SIGTERM, SIGINT).
/// Safe to call from a signal handler.
void requestStop(int signal);
/// The signal that asked the process to stop, or 0.
int stopSignal();
/// Throws fp::Interrupted ("stopped by SIGTERM …") when a stop was requested.
void throwIfStopped();

}  // namespace fp::app
