#include "serve/Requests.h"

#include "foundation/Limits.h"
#include "io/JsonFile.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>

namespace fp::serve {

namespace {

// A setting's value as the body gives it: a bool, a number or a string, typed as it is.
void checkValue(const nlohmann::json& v, const std::string& pointer) {
    if (v.is_string() || v.is_boolean() || v.is_number()) return;
    throw RequestError(400, fmt::format("{}: a value is a bool, a number or a string, not {}",
                                        pointer, v.dump()),
                       pointer);
}

// The body's "cvars", "set" or "inputs" (key) into `out`.
void readSettings(const nlohmann::json& j, const std::string& key, app::Settings& out) {
    if (!j.contains(key)) return;
    const nlohmann::json& map = j[key];
    if (!map.is_object())
        throw RequestError(400, fmt::format("/{}: expected an object of name → value", key),
                           "/" + key);
    for (const auto& [name, value] : map.items()) {
        const std::string pointer = "/" + key + "/" + name;
        if (name.empty())
            throw RequestError(400, fmt::format("{}: '' is not a name", pointer), pointer);
        checkValue(value, pointer);
        // (Filled directly: the request parser links nothing of the passes, and a JSON object
        // names each key once; cvars spelled alike in two cases meet in the planner.)
        if (key == "cvars") out.cvars[name] = value;
        else if (key == "set") out.sets.emplace_back(name, value);
        else if (!value.is_string())
            throw RequestError(400, fmt::format("{}: an input is rebound to a source's name "
                                                "(\"pass.port\" or \"capture:Buffer\"), not {}",
                                                pointer, value.dump()),
                               pointer);
        else out.inputs.emplace_back(name, value.get<std::string>());
    }
}

std::optional<std::string> single(const std::multimap<std::string, std::string>& query,
                                  const std::string& key) {
    const auto range = query.equal_range(key);
    if (range.first == range.second) return std::nullopt;
    if (std::next(range.first) != range.second)
        throw RequestError(400, fmt::format("?{} is given twice", key));
    return range.first->second;
}

}  // namespace

SettingsChange parseSettingsChange(std::string_view body) {
    if (body.size() > kMaxRequestBody)
        throw RequestError(413, fmt::format("the body is {} bytes; a settings change is at most {}",
                                            body.size(), kMaxRequestBody));
    nlohmann::json j;
    try {
        j = io::parseJsonLimited(std::string(body), "the request body");
    } catch (const Error& e) {
        throw RequestError(400, e.what());
    }
    if (!j.is_object())
        throw RequestError(400, "the body is a JSON object: {\"cvars\": {…}, \"set\": {…}, "
                                "\"inputs\": {…}, \"frame\": N}");
    for (const auto& [key, value] : j.items())
        if (key != "cvars" && key != "set" && key != "inputs" && key != "frame" && key != "show")
            throw RequestError(400, fmt::format("unknown key '{}': the body has \"cvars\", "
                                                "\"set\", \"inputs\", \"frame\" and \"show\"",
                                                key),
                               "/" + key);
    SettingsChange change;
    // A refused setting is named by its place in the body.
    change.settings.cvarOrigin = "/cvars/{}";
    change.settings.setOrigin = "/set/{}";
    change.settings.inputOrigin = "/inputs/{}";
    readSettings(j, "cvars", change.settings);
    readSettings(j, "set", change.settings);
    readSettings(j, "inputs", change.settings);
    if (j.contains("frame")) {
        const nlohmann::json& f = j["frame"];
        if (!f.is_number_integer() || f.get<int64_t>() < -limits::kMaxFrameNumber ||
            f.get<int64_t>() > limits::kMaxFrameNumber)
            throw RequestError(400, fmt::format("/frame: {} is not a frame number", f.dump()),
                               "/frame");
        change.frame = int(f.get<int64_t>());
    }
    if (j.contains("show")) {
        const nlohmann::json& show = j["show"];
        if (!show.is_array() || show.size() > kMaxShown)
            throw RequestError(400, fmt::format("/show: a list of at most {} buffer names", kMaxShown),
                               "/show");
        change.show.emplace();
        for (std::size_t i = 0; i < show.size(); ++i) {
            const std::string where = fmt::format("/show/{}", i);
            if (!show[i].is_string())
                throw RequestError(400, fmt::format("{}: {} is not a buffer name", where,
                                                    show[i].dump().substr(0, 64)),
                                   where);
            try {
                change.show->push_back(parseBufferQuery(show[i].get<std::string>(), {}).name);
            } catch (const RequestError& e) {
                throw RequestError(400, fmt::format("{}: {}", where, e.what()), where);
            }
        }
    }
    return change;
}

BufferQuery parseBufferQuery(std::string_view name,
                             const std::multimap<std::string, std::string>& query) {
    BufferQuery q;
    if (name.empty() || name.size() > 256 || name.find("..") != std::string_view::npos ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-") !=
            std::string_view::npos)
        throw RequestError(400, fmt::format("'{}' is not a buffer name (PASS.PORT, a capture "
                                            "buffer or Truth.LAYER)",
                                            std::string(name.substr(0, 256))));
    q.name = std::string(name);
    if (const auto f = single(query, "format")) {
        if (*f == "raw") q.format = BufferFormat::Raw;
        else if (*f == "exr") q.format = BufferFormat::Exr;
        else if (*f == "png") q.format = BufferFormat::Png;
        else throw RequestError(400, fmt::format("?format={}: raw, exr or png", *f));
    }
    if (const auto t = single(query, "type")) {
        if (*t == "half") q.half = true;
        else if (*t != "float") throw RequestError(400, fmt::format("?type={}: float or half", *t));
    }
    if (const auto f = single(query, "frame")) {
        int64_t frame = 0;
        const auto [end, ec] = std::from_chars(f->data(), f->data() + f->size(), frame);
        if (ec != std::errc() || end != f->data() + f->size() ||
            frame < -limits::kMaxFrameNumber || frame > limits::kMaxFrameNumber)
            throw RequestError(400, fmt::format("?frame={}: not a frame number", *f));
        q.frame = int(frame);
    }
    return q;
}

TevRequest parseTevRequest(std::string_view body) {
    if (body.size() > kMaxRequestBody)
        throw RequestError(413, fmt::format("the body is {} bytes; at most {}", body.size(),
                                            kMaxRequestBody));
    nlohmann::json j;
    try {
        j = io::parseJsonLimited(std::string(body), "the request body");
    } catch (const Error& e) {
        throw RequestError(400, e.what());
    }
    if (!j.is_object() || !j.contains("buffers") || !j["buffers"].is_array() ||
        j["buffers"].empty())
        throw RequestError(400, "the body is {\"host\": \"127.0.0.1:14158\", \"buffers\": "
                                "[\"pass.port\", …]}");
    TevRequest r;
    for (const auto& b : j["buffers"]) {
        if (!b.is_string()) throw RequestError(400, "/buffers: names are strings", "/buffers");
        r.buffers.push_back(parseBufferQuery(b.get<std::string>(), {}).name);
    }
    if (j.contains("host")) {
        if (!j["host"].is_string()) throw RequestError(400, "/host: a string", "/host");
        r.address = j["host"].get<std::string>();
        // 127.0.0.1[:port], localhost[:port], [::1]:port or ::1.
        std::string host = r.address;
        if (!host.empty() && host.front() == '[') host = host.substr(1, host.find(']') - 1);
        else if (std::count(host.begin(), host.end(), ':') == 1) host = host.substr(0, host.find(':'));
        if (host != "127.0.0.1" && host != "localhost" && host != "::1")
            throw RequestError(400,
                               fmt::format("/host: '{}' is not this machine (127.0.0.1, localhost "
                                           "or ::1): the workbench pushes to a local tev only",
                                           r.address),
                               "/host");
    }
    return r;
}

int parseRays(const std::multimap<std::string, std::string>& query) {
    const auto r = single(query, "rays");
    if (!r) return 32;
    int rays = 0;
    const auto [end, ec] = std::from_chars(r->data(), r->data() + r->size(), rays);
    if (ec != std::errc() || end != r->data() + r->size())
        throw RequestError(400, fmt::format("?rays={}: a whole number", *r));
    return rays;
}

bool parseWait(const std::multimap<std::string, std::string>& query) {
    const auto w = single(query, "wait");
    if (!w || *w == "1" || *w == "true") return true;
    if (*w == "0" || *w == "false") return false;
    throw RequestError(400, fmt::format("?wait={}: 0 or 1", *w));
}

std::string errorBody(int status, const std::string& message, const std::string& pointer) {
    nlohmann::json j = {{"error", message}, {"status", status}};
    if (!pointer.empty()) j["pointer"] = pointer;
    // A name from the request may be any bytes: invalid UTF-8 is replaced, never thrown on.
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace fp::serve
