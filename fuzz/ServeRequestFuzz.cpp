// Fuzz target: what a client of `framepass serve` sends (serve/Requests.cpp). The first byte picks
// the request: a PUT /api/params body, or a GET /api/buffer name with a query of key=value pairs
// (split on '&' and '='). Every answer is a RequestError (a 4xx) or a parsed request, and an
// error body is always valid JSON whatever bytes the message quotes.
#include "fuzz/FuzzSupport.h"
#include "serve/Requests.h"

#include <nlohmann/json.hpp>

#include <map>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
    return fp::fuzz::expectCleanErrors([&] {
        try {
            if (data[0] % 2 == 0) {
                fp::serve::parseSettingsChange(text);
            } else {
                const auto q = text.find('?');
                std::multimap<std::string, std::string> query;
                if (q != std::string::npos) {
                    std::string rest = text.substr(q + 1);
                    while (!rest.empty()) {
                        const auto amp = rest.find('&');
                        const std::string pair = rest.substr(0, amp);
                        const auto eq = pair.find('=');
                        query.emplace(pair.substr(0, eq),
                                      eq == std::string::npos ? "" : pair.substr(eq + 1));
                        rest = amp == std::string::npos ? "" : rest.substr(amp + 1);
                    }
                }
                fp::serve::parseBufferQuery(text.substr(0, q), query);
                fp::serve::parseWait(query);
            }
        } catch (const fp::serve::RequestError& e) {
            if (e.status() < 400 || e.status() > 499) std::abort();
            (void)nlohmann::json::parse(fp::serve::errorBody(e.status(), e.what(), e.pointer()));
            throw;
        }
    });
}
