#pragma once
// Errors for bad input are exceptions with context (docs/design.md, Errors); asserts are for bugs.
#include <fmt/format.h>

#include <cassert>
#include <stdexcept>
#include <string>
#include <vector>

namespace fp {

/// Process exit codes, documented in docs/commands.md ("Exit codes").
enum class ExitCode : int {
    Ok = 0,
    FrameFailed = 1,  //!< a frame could not be processed (bad pixels, I/O error, ...)
    Usage = 2,        //!< bad command line, config or plan: nothing was computed
    Interrupted = 130,  //!< stopped by SIGINT (128 + 2), as shells report it
    Terminated = 143,   //!< stopped by SIGTERM (128 + 15): a farm's pre-emption
};

/// A runtime or input error. The message names the file, channel, JSON pointer or frame.
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message, ExitCode code = ExitCode::FrameFailed)
        : std::runtime_error(message), mCode(code) {}
    ExitCode code() const { return mCode; }

private:
    ExitCode mCode;
};

/// One problem of a config: where it is (a JSON pointer such as /passes/2/params/rays, or the
/// command-line option that set the value, such as "--cvar r.SSGI.Quality") and what is wrong.
struct ConfigProblem {
    std::string pointer;
    std::string message;
};

/// A usage or configuration error (exit code 2). One about a config's contents also says which
/// file (`path`) and lists each problem with its JSON pointer, for doors that show them apart
/// (the Python module's ConfigError.pointer and .path).
class UsageError : public Error {
public:
    explicit UsageError(const std::string& message, std::string path = {},
                        std::vector<ConfigProblem> problems = {})
        : Error(message, ExitCode::Usage),
          mPath(std::move(path)),
          mProblems(std::move(problems)) {}
    const std::string& path() const { return mPath; }
    const std::vector<ConfigProblem>& problems() const { return mProblems; }

private:
    std::string mPath;
    std::vector<ConfigProblem> mProblems;
};

/// A setting refused when it was made (a Python call, a server request), the session left as it
/// was: its name is unknown, its value has the wrong type, or the value is not one the setting
/// takes. The doors raise it as their language's error of that kind (KeyError, TypeError,
/// ValueError in Python).
class SettingError : public UsageError {
public:
    enum class Kind { UnknownName, WrongType, BadValue };
    SettingError(Kind kind, const std::string& message, std::vector<ConfigProblem> problems = {})
        : UsageError(message, {}, std::move(problems)), mKind(kind) {}
    Kind kind() const { return mKind; }

private:
    Kind mKind;
};

/// A run stopped by a signal at a safe point (exit 128 + the signal).
class Interrupted : public Error {
public:
    explicit Interrupted(int signal, const std::string& message)
        : Error(message, static_cast<ExitCode>(128 + signal)), mSignal(signal) {}
    int signal() const { return mSignal; }

private:
    int mSignal;
};

/// A run cancelled from another thread (a newer request superseded it) at a safe point.
class Cancelled : public Error {
public:
    explicit Cancelled(const std::string& message) : Error(message, ExitCode::Interrupted) {}
};

}  // namespace fp

#define FP_CHECK(cond, ...)                                  \
    do {                                                     \
        if (!(cond)) throw ::fp::Error(fmt::format(__VA_ARGS__)); \
    } while (0)

#define FP_ASSERT(cond) assert(cond)
