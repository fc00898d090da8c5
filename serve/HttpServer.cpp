#include "serve/HttpServer.h"

#include "color/DisplayTransform.h"
#include "io/ExrWriter.h"
#include "io/PngWriter.h"
#include "io/TevClient.h"
#include "serve/PageAssets.h"
#include "serve/Requests.h"

#include <Imath/half.h>
#include <httplib.h>

#include <atomic>
#include <cerrno>
#include <random>
#include <sstream>
#include <sys/socket.h>
#include <unistd.h>

namespace fp::serve {

namespace {

std::string jsonText(const nlohmann::json& j) {
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void sendJson(httplib::Response& res, const nlohmann::json& j) {
    res.set_header("Cache-Control", "no-store");
    res.set_content(jsonText(j), "application/json");
}

void sendError(httplib::Response& res, int status, const std::string& message,
               const std::string& pointer = "") {
    res.status = status;
    res.set_content(errorBody(status, message, pointer), "application/json");
}

// The pixels as little-endian float32 or float16, interleaved (row 0 the top), the page's and a
// script's raw form; what they are travels in headers.
std::string rawPixels(const Image& image, bool half) {
    const int w = image.width(), h = image.height(), c = image.channelCount();
    const std::size_t values = std::size_t(w) * h * c;
    std::string out(values * (half ? 2 : 4), '\0');
    char* p = out.data();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < c; ++k) {
                const float v = image.plane(k).at(x, y);
                if (half) {
                    const uint16_t bits = Imath::half(v).bits();
                    std::memcpy(p, &bits, 2);
                    p += 2;
                } else {
                    std::memcpy(p, &v, 4);
                    p += 4;
                }
            }
    return out;
}

// A table's planes one after another (R, then G, B), each row after row, as float32: the page's
// display tables.
std::string planarBytes(const Image& table) {
    std::string out;
    for (int c = 0; c < table.channelCount(); ++c)
        for (int y = 0; y < table.height(); ++y)
            out.append(reinterpret_cast<const char*>(table.plane(c).row(y)),
                       std::size_t(table.width()) * sizeof(float));
    return out;
}

// An EXR of one buffer, encoded in memory (no file: nothing for another user to read).
std::string exrBytes(const BufferImage& b) {
    io::ExrMetadata meta;
    meta.frame = b.frame;
    const std::vector<char> bytes =
        io::encodeExr(b.name + ".exr", {{"", {{b.name, &b.image, false}}}}, meta);
    return std::string(bytes.begin(), bytes.end());
}

// Whether `host` is this machine only: a loopback address or name.
bool isLoopback(const std::string& host) {
    return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

// `host` as a URL writes it: an IPv6 address in brackets.
std::string urlHost(const std::string& host) {
    return host.find(':') != std::string::npos ? "[" + host + "]" : host;
}

// A random token of 128 bits, in hex: what a client off this machine must show.
std::string newToken() {
    std::random_device random;
    std::string token;
    for (int i = 0; i < 4; ++i) token += fmt::format("{:08x}", uint32_t(random()));
    return token;
}

// The value of cookie `name` in a Cookie header, or "".
std::string cookie(const std::string& header, const std::string& name) {
    std::size_t at = 0;
    while (at < header.size()) {
        const std::size_t end = std::min(header.find(';', at), header.size());
        std::string pair = header.substr(at, end - at);
        pair.erase(0, pair.find_first_not_of(' '));
        if (pair.rfind(name + "=", 0) == 0) return pair.substr(name.size() + 1);
        at = end + 1;
    }
    return "";
}

}  // namespace

WorkbenchServer::WorkbenchServer(Workbench& workbench, const std::string& host, int port)
    : mWorkbench(workbench), mServer(std::make_unique<httplib::Server>()), mHost(host),
      mToken(isLoopback(host) ? "" : newToken()),
      mEventStreams(std::make_shared<std::atomic<int>>(0)) {
    // An event stream holds a thread while open: the pool has one for each stream allowed
    // (kMaxEventStreams; one more is refused, 503) and kRequestThreads more for requests. An idle
    // connection holds a request thread for at most the keep-alive or read timeout (2 s).
    mServer->new_task_queue = [] { return new httplib::ThreadPool(kMaxEventStreams + kRequestThreads); };
    mServer->set_keep_alive_timeout(2);
    mServer->set_read_timeout(2, 0);
    mServer->set_payload_max_length(kMaxRequestBody);
    // SO_REUSEADDR alone (a restart binds while the last connections close), not cpp-httplib's
    // SO_REUSEPORT, with which a second server on the port would start and share the requests.
    mServer->set_socket_options([](socket_t sock) {
        int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    });
    guard();
    routes();
    errno = 0;
    mPort = port == 0 ? mServer->bind_to_any_port(host) : (mServer->bind_to_port(host, port) ? port : -1);
    if (mPort <= 0 && errno == EADDRINUSE)
        throw UsageError(fmt::format("--port {}: the port is in use (another framepass serve?); "
                                     "stop it, or pick another port (--port 0 picks a free one)",
                                     port));
    if (mPort <= 0)
        throw UsageError(fmt::format("--host {} --port {}: cannot listen there (not an address "
                                     "of this machine?)",
                                     host, port));
}

WorkbenchServer::~WorkbenchServer() = default;

std::string WorkbenchServer::url() const {
    // Every address (0.0.0.0, ::): the machine's name is how another machine reaches it.
    std::string name = mHost;
    if (mHost == "0.0.0.0" || mHost == "::") {
        char buffer[256] = {};
        name = ::gethostname(buffer, sizeof(buffer) - 1) == 0 ? buffer : "127.0.0.1";
    }
    return fmt::format("http://{}:{}/{}", urlHost(name), mPort,
                       mToken.empty() ? "" : "?token=" + mToken);
}

bool WorkbenchServer::onlyThisMachine() const { return mToken.empty(); }

void WorkbenchServer::guard() {
    // Who may talk to the session. On a loopback address only this machine reaches the port, but
    // a web page elsewhere can point its own name at 127.0.0.1 (DNS rebinding) and have the
    // browser send it requests: a request must name the address served in its Host, and a
    // browser's cross-site request (its Origin another site) is refused. Off loopback, anyone who
    // reaches the port could: a request must also carry the token of the printed URL, as
    // ?token= or the cookie the page gets when it is opened with it.
    mServer->set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
        using R = httplib::Server::HandlerResponse;
        const std::string host = req.get_header_value("Host");
        const std::string port = fmt::format(":{}", mPort);
        if (onlyThisMachine()) {
            bool known = false;
            for (const std::string& name : {std::string("127.0.0.1"), std::string("localhost"),
                                           std::string("[::1]"), urlHost(mHost)})
                known = known || host == name + port;
            if (!known) {
                sendError(res, 403, fmt::format("Host '{}' is not this server's address ({}{})",
                                                host, urlHost(mHost), port));
                return R::Handled;
            }
        }
        const std::string origin = req.get_header_value("Origin");
        if (!origin.empty() && origin != "http://" + host) {
            sendError(res, 403, fmt::format("a request from another site ({}) is refused", origin));
            return R::Handled;
        }
        if (!mToken.empty()) {
            const std::string given = req.has_param("token")
                                          ? req.get_param_value("token")
                                          : cookie(req.get_header_value("Cookie"), "framepass_token");
            if (given != mToken) {
                sendError(res, 403, "this workbench is open to the network: open the URL it "
                                    "printed, with its ?token=");
                return R::Handled;
            }
            // The page opened with the token keeps it for its own requests and event stream.
            if (req.has_param("token"))
                res.set_header("Set-Cookie", "framepass_token=" + mToken +
                                                 "; Path=/; HttpOnly; SameSite=Strict");
        }
        return R::Unhandled;
    });
}

void WorkbenchServer::run() { mServer->listen_after_bind(); }

void WorkbenchServer::stop() {
    mWorkbench.stop();
    mServer->stop();
}

void WorkbenchServer::routes() {
    httplib::Server& s = *mServer;
    Workbench& wb = mWorkbench;

    for (const PageAsset& asset : pageAssets())
        s.Get(std::string(asset.path), [asset](const httplib::Request&, httplib::Response& res) {
            res.set_content(std::string(asset.body),
                            std::string(asset.contentType) + "; charset=utf-8");
        });

    s.Get("/favicon.ico", [](const httplib::Request&, httplib::Response& res) { res.status = 204; });
    // The JSON reads, each one Workbench call.
    const std::pair<const char*, nlohmann::json (Workbench::*)()> reads[] = {
        {"/api/graph", &Workbench::graph},         {"/api/params", &Workbench::params},
        {"/api/report", &Workbench::report},       {"/api/export", &Workbench::exportSettings},
        {"/api/buffers", &Workbench::bufferNames}, {"/api/displays", &Workbench::displays},
        {"/api/status", &Workbench::status}};
    for (const auto& [path, read] : reads)
        s.Get(path, [&wb, read = read](const httplib::Request&, httplib::Response& res) {
            sendJson(res, (wb.*read)());
        });
    // The last run's errors taken apart (an oracle trace and 8 converged traces: seconds).
    s.Get("/api/breakdown", [&wb](const httplib::Request& req, httplib::Response& res) {
        sendJson(res, wb.breakdown(parseRays(req.params)));
    });
    s.Delete("/api/breakdown", [&wb](const httplib::Request&, httplib::Response& res) {
        sendJson(res, wb.cancelBreakdown());
    });
    // The display view baked over every half value: 3 planes of 65536 float32 (R, then G, B).
    s.Get("/api/lut", [&wb](const httplib::Request& req, httplib::Response& res) {
        const std::string view = req.has_param("view") ? req.get_param_value("view") : "";
        const std::optional<Image> lut = wb.displayTable(view);
        if (!lut)
            return sendError(res, 422, fmt::format("view '{}' mixes channels: it has no "
                                                   "per-channel table",
                                                   view));
        res.set_header("X-Entries", std::to_string(lut->width()));
        res.set_content(planarBytes(*lut), "application/octet-stream");
    });

    // Unreal 4.27's filmic tonemapper (its defaults) and the sRGB encoding baked into a 65³
    // table over log2 of each channel: 3 planes of 65³ float32 (R, then G, B), entry r + 65·g +
    // 65²·b; its size and log2 range in headers. The page's "UE 4.27 film" view.
    s.Get("/api/film-cube", [](const httplib::Request&, httplib::Response& res) {
        constexpr int kSize = 65;
        // The same for every request: baked on the first (275k pixels of the curve).
        static const std::string cube =
            planarBytes(DisplayTransform::filmCube(color::FilmParams{}, kSize));
        res.set_header("X-Size", std::to_string(kSize));
        res.set_header("X-Log2-Min", fmt::format("{}", DisplayTransform::kFilmCubeLog2Min));
        res.set_header("X-Log2-Max", fmt::format("{}", DisplayTransform::kFilmCubeLog2Max));
        res.set_content(cube, "application/octet-stream");
    });

    s.Put("/api/params", [&wb](const httplib::Request& req, httplib::Response& res) {
        const SettingsChange change = parseSettingsChange(req.body);
        const bool wait = parseWait(req.params);
        std::vector<Diagnostic> warned;
        const uint64_t generation = wb.apply(change, &warned);
        // What the change warns of, by its place in the body (a cvar that a config parameter
        // shadows has no effect: the page says so beside it).
        nlohmann::json warnings = nlohmann::json::array();
        for (const auto& w : warned) warnings.push_back({{"pointer", w.pointer}, {"message", w.message}});
        if (!wait) {
            res.status = 202;
            return sendJson(res, {{"generation", generation}, {"status", "queued"},
                                  {"warnings", warnings}});
        }
        nlohmann::json outcome = wb.waitFor(generation);
        outcome["warnings"] = warnings;
        outcome["report"] = wb.report();
        sendJson(res, outcome);
    });

    s.Get(R"(/api/buffer/(.*))", [&wb](const httplib::Request& req, httplib::Response& res) {
        const BufferQuery q = parseBufferQuery(req.matches[1].str(), req.params);
        const BufferImage b = wb.buffer(q.name, q.frame);
        std::string channels;
        for (const auto& c : b.image.channels()) channels += (channels.empty() ? "" : ",") + c;
        res.set_header("X-Width", std::to_string(b.image.width()));
        res.set_header("X-Height", std::to_string(b.image.height()));
        res.set_header("X-Channels", channels);
        res.set_header("X-Frame", std::to_string(b.frame));
        res.set_header("X-Generation", std::to_string(b.generation));
        res.set_header("X-Color", b.color ? "1" : "0");
        res.set_header("Cache-Control", "no-store");
        switch (q.format) {
            case BufferFormat::Raw:
                res.set_header("X-Type", q.half ? "float16" : "float32");
                res.set_content(rawPixels(b.image, q.half), "application/octet-stream");
                break;
            case BufferFormat::Exr:
                res.set_content(exrBytes(b), "image/x-exr");
                break;
            case BufferFormat::Png: {
                // Colour through the OCIO display's default view, data as it is, clamped.
                const DisplayTransform display(b.color ? wb.displayConfig() : nullptr,
                                               "scene_linear", "", "", 0.0f, b.color);
                res.set_content(io::encodePng(display.apply(b.image)), "image/png");
                break;
            }
        }
    });

    // The buffers shown, pushed to a tev viewer on this machine.
    s.Post("/api/tev", [&wb](const httplib::Request& req, httplib::Response& res) {
        const TevRequest r = parseTevRequest(req.body);
        std::vector<BufferImage> images;
        for (const auto& name : r.buffers) images.push_back(wb.buffer(name, std::nullopt));
        try {
            io::TevClient tev(r.address);
            nlohmann::json sent = nlohmann::json::array();
            for (const auto& b : images) {
                const std::string name = fmt::format("{} (frame {})", b.name, b.frame);
                tev.sendImage(name, b.image, &b == &images.front());
                sent.push_back(name);
            }
            sendJson(res, {{"images", sent}, {"host", r.address}});
        } catch (const Error& e) {
            sendError(res, 502, e.what());
        }
    });

    // Server-sent events: {"seq", "type": pass|frame|cancelled|error, …} as runs progress.
    s.Get("/api/events", [&wb, streams = mEventStreams](const httplib::Request& req,
                                                        httplib::Response& res) {
        if (++*streams > kMaxEventStreams) {
            --*streams;
            return sendError(res, 503, fmt::format("{} event streams are open, the most this "
                                                   "workbench serves at once",
                                                   kMaxEventStreams));
        }
        uint64_t after = 0;
        if (req.has_header("Last-Event-ID"))
            after = std::strtoull(req.get_header_value("Last-Event-ID").c_str(), nullptr, 10);
        auto cursor = std::make_shared<uint64_t>(after);
        res.set_header("Cache-Control", "no-store");
        res.set_chunked_content_provider(
            "text/event-stream", [&wb, cursor](std::size_t, httplib::DataSink& sink) {
                if (wb.stopped()) {
                    sink.done();
                    return true;
                }
                const auto events = wb.eventsAfter(*cursor, std::chrono::milliseconds(1000));
                std::string out;
                for (const auto& [seq, json] : events) {
                    out += fmt::format("id: {}\ndata: {}\n\n", seq, json);
                    *cursor = seq;
                }
                if (out.empty()) out = ": keep-alive\n\n";
                return sink.write(out.data(), out.size());
            },
            [streams](bool) { --*streams; });
    });

    s.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
            try {
                std::rethrow_exception(ep);
            } catch (const RequestError& e) {
                sendError(res, e.status(), e.what(), e.pointer());
            } catch (const UsageError& e) {
                sendError(res, 400, e.what(),
                          e.problems().empty() ? "" : e.problems().front().pointer);
            } catch (const std::exception& e) {
                sendError(res, 500, e.what());
            } catch (...) {
                sendError(res, 500, "unknown error");
            }
        });
    s.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;  // an answer with its own JSON error
        if (res.status == 404)
            return sendError(res, 404, fmt::format("no {} {}: the API is documented in "
                                                   "docs/serve.md",
                                                   req.method, req.path));
        if (res.status == 413)
            return sendError(res, 413, fmt::format("the body is larger than {} bytes",
                                                   kMaxRequestBody));
        sendError(res, res.status, fmt::format("HTTP {}", res.status));
    });
}

}  // namespace fp::serve
