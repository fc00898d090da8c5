// framepass serve: the look-dev workbench in the browser (docs/serve.md), a door onto one library
// session through serve/.
#include "cli/Commands.h"
#include "cli/Flags.h"
#include "serve/HttpServer.h"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <thread>

namespace fp::cli {

Command addServeCommand(CLI::App& app) {
    auto opt = std::make_shared<app::SetupOptions>();
    auto host = std::make_shared<std::string>("127.0.0.1");
    auto port = std::make_shared<int>(8080);
    auto open = std::make_shared<bool>(false);
    CLI::App* sub = app.add_subcommand(
        "serve",
        "the look-dev workbench: a local web page with the chain, any buffer, a slider for "
        "every cvar and parameter, truth side by side, re-run live (and its JSON API)");
    sub->add_option("config", opt->config, "run config JSON")->required();
    sub->add_option("--capture", opt->capture, "capture file or pattern (overrides the config's)");
    sub->add_option("--profile", opt->profile, "capture profile (overrides the config's)");
    sub->add_option("--device", opt->device, "cpu or cuda (overrides the config's)")
        ->check(CLI::IsMember({"cpu", "cuda"}));
    sub->add_option("--frames", opt->frames, "the frames the frame slider offers");
    sub->add_option("--host", *host,
                    "address to listen on (default 127.0.0.1: this machine only; 0.0.0.0 "
                    "opens it to the network, with a token in the printed URL)");
    sub->add_option("--port", *port, "port (default 8080; 0 picks a free one)")
        ->check(CLI::Range(0, 65535));
    sub->add_flag("--open", *open, "open the page in the desktop's browser (xdg-open)");

    return [opt, host, port, open]() {
        catchStopSignals();
        serve::Workbench workbench(*opt);
        serve::WorkbenchServer server(workbench, *host, *port);
        std::cout << "framepass serve: " << server.url() << " (Ctrl-C stops)" << std::endl;
        if (!server.onlyThisMachine())
            logWarning(fmt::format("--host {}: the workbench is open to every machine that "
                                   "reaches port {} here; whoever has the URL above (its token) "
                                   "can read every buffer and change the settings",
                                   *host, server.port()));
        if (*open) {
            const std::string command = "xdg-open '" + server.url() + "' >/dev/null 2>&1 &";
            if (std::system(command.c_str()) != 0)
                logWarning("--open: xdg-open failed; open " + server.url() + " yourself");
        }
        // The signal handler only sets a flag (app::requestStop): watch it from here.
        std::thread watcher([&server] {
            while (app::stopSignal() == 0)
                std::this_thread::sleep_for(std::chrono::milliseconds(100));
            server.stop();
        });
        server.run();
        if (app::stopSignal() == 0) app::requestStop(SIGTERM);  // the server stopped by itself
        watcher.join();
        std::cout << "framepass serve: stopped" << std::endl;
        return 0;
    };
}

}  // namespace fp::cli
