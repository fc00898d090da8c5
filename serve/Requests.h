#pragma once
// The parse side of the workbench's HTTP API (docs/serve.md): request bodies and query strings
// read into what the Workbench takes, every problem a RequestError with its HTTP status. Nothing
// here touches a file or the session, so the fuzz target (fuzz/ServeRequestFuzz.cpp) runs it
// alone.
#include "app/Settings.h"
#include "foundation/Error.h"

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fp::serve {

/// A request that cannot be served, with the HTTP status that says why (400 bad value, 404
/// unknown name, 409 no run finished, 413 too large).
class RequestError : public UsageError {
public:
    RequestError(int status, const std::string& message, std::string pointer = {})
        : UsageError(message), mStatus(status), mPointer(std::move(pointer)) {}
    int status() const { return mStatus; }
    const std::string& pointer() const { return mPointer; }

private:
    int mStatus;
    std::string mPointer;
};

/// A change of settings, as PUT /api/params sends it: cvars and PASS.PARAM values (as --cvar and
/// --set read them) and the frame to show.
struct SettingsChange {
    app::Settings settings;  //!< "cvars", "set" and "inputs", values as the body gives them
    std::optional<int> frame;
    /// The buffers the page shows (replacing the last list): the pass outputs among them are
    /// handed back by every run; the others stay where they are made (on the GPU, unread).
    std::optional<std::vector<std::string>> show;
};

/// The most a request body may hold: a settings change is a few hundred bytes.
inline constexpr std::size_t kMaxRequestBody = 64 * 1024;
/// Event streams open at once; each holds one of the server's threads while open, so the
/// threads are this many plus kRequestThreads, and idle streams can never starve a request.
inline constexpr int kMaxEventStreams = 32;
/// Threads for requests. A connection that sends nothing holds one until the read timeout
/// (2 s): 16 such clients leave 16 threads answering.
inline constexpr int kRequestThreads = 32;
/// The most buffers a page may show at once (A, B, and what the probe reads).
inline constexpr std::size_t kMaxShown = 16;

/// PUT /api/params: {"cvars": {NAME: value}, "set": {"PASS.PARAM": value}, "inputs":
/// {"PASS.INPUT": "source"}, "frame": N,
/// "show": [BUFFER, …]}, values bool, number or string; buffer names as parseBufferQuery takes
/// them, at most kMaxShown. Throws RequestError 400 (malformed JSON, unknown key, a value that is
/// an object, array or null) or 413 (over kMaxRequestBody).
SettingsChange parseSettingsChange(std::string_view body);

enum class BufferFormat { Raw, Exr, Png };

/// GET /api/buffer/<name>?format=raw|exr|png&type=float|half&frame=N.
struct BufferQuery {
    std::string name;
    BufferFormat format = BufferFormat::Raw;
    bool half = false;  //!< raw as float16 instead of float32
    std::optional<int> frame;
};

/// Throws RequestError 400 for a bad format, type or frame, and for a name that could be a path
/// (a buffer name is letters, digits, '.', '_' and '-', and no "..").
BufferQuery parseBufferQuery(std::string_view name,
                             const std::multimap<std::string, std::string>& query);

/// POST /api/tev: {"host": "127.0.0.1:14158", "buffers": ["pass.port", …]}. The host is a
/// loopback address (127.0.0.1, localhost, ::1): the server does not connect elsewhere for a page.
struct TevRequest {
    std::string address = "127.0.0.1:14158";
    std::vector<std::string> buffers;
};
TevRequest parseTevRequest(std::string_view body);

/// ?rays=N of GET /api/breakdown (default 32); the range is the Workbench's to check.
int parseRays(const std::multimap<std::string, std::string>& query);

/// ?wait=0|1 (default 1): whether PUT /api/params answers after the run.
bool parseWait(const std::multimap<std::string, std::string>& query);

/// The JSON error body every 4xx answer carries: {"error", "status", "pointer"?}.
std::string errorBody(int status, const std::string& message, const std::string& pointer = "");

}  // namespace fp::serve
