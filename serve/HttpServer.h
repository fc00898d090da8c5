#pragma once
// The workbench's HTTP door (docs/serve.md): cpp-httplib serving the page and the JSON API over
// one Workbench. Every answer to a bad request is a 4xx with a JSON error body; no request
// reaches a file other than the session's own inputs (buffer names are looked up, never opened).
#include "serve/Workbench.h"

#include <atomic>
#include <memory>
#include <string>

namespace httplib {
class Server;
}

namespace fp::serve {

class WorkbenchServer {
public:
    /// Binds `host`:`port` (port 0: any free port). Throws fp::UsageError when it cannot.
    WorkbenchServer(Workbench& workbench, const std::string& host, int port);
    ~WorkbenchServer();

    int port() const { return mPort; }
    /// The page's URL: for an address off this machine, with the token requests must carry.
    std::string url() const;
    /// Whether only this machine reaches the server (a loopback --host).
    bool onlyThisMachine() const;
    /// Serves until stop() (from another thread, or a signal handler's poller).
    void run();
    void stop();

private:
    void routes();
    /// Refuses requests from elsewhere: a foreign Host or Origin, and off loopback a missing
    /// token (403).
    void guard();
    Workbench& mWorkbench;
    std::unique_ptr<httplib::Server> mServer;
    std::string mHost;
    std::string mToken;  // "" on a loopback address
    int mPort = 0;
    std::shared_ptr<std::atomic<int>> mEventStreams;  // open now (at most kMaxEventStreams)
};

}  // namespace fp::serve
