#pragma once
// The workbench's HTTP door (docs/serve.md): cpp-httplib serving the page and the JSON API over
// one Workbench. Every answer to a bad request is a 4xx with a JSON error body; no request
// reaches a file other than the session's own inputs (buffer names are looked up, never opened).
#include "serve/Workbench.h"

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
    std::string url() const;
    /// Serves until stop() (from another thread, or a signal handler's poller).
    void run();
    void stop();

private:
    void routes();
    Workbench& mWorkbench;
    std::unique_ptr<httplib::Server> mServer;
    std::string mHost;
    int mPort = 0;
};

}  // namespace fp::serve
