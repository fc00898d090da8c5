// framepass plan: the resolved graph, without reading a pixel (app/PlanReport.h does the work).
#include "app/PlanReport.h"
#include "cli/Commands.h"
#include "cli/Flags.h"
#include "io/SafeFiles.h"

#include <iostream>

namespace fp::cli {

Command addPlanCommand(CLI::App& app) {
    struct Options {
        SetupOptions session;
        bool json = false;
        std::string dot;
    };
    auto opt = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand("plan",
                                       "show the resolved pass graph in order, the capture "
                                       "channels it reads, peak memory and culled passes");
    addSetupOptions(*sub, opt->session);
    sub->add_flag("--json", opt->json, "machine-readable output");
    sub->add_option("--dot", opt->dot,
                    "write the resolved chain as a Graphviz graph (passes and ports, CPU blue, GPU "
                    "green, culled passes grey) to FILE, or - for stdout (dot -Tsvg renders it)")
        ->check(nonEmptyPath());

    return [opt]() {
        const RunSetup session(opt->session);
        for (const auto& w : session.plan().warnings)
            logWarning(fmt::format("{}: {}", w.pointer, w.message));
        const nlohmann::json j = planJson(session, opt->session.config);
        if (opt->dot == "-") {
            std::cout << planDot(session.plan());
            return 0;
        }
        if (!opt->dot.empty()) io::writeFileAtomically(opt->dot, planDot(session.plan()));
        if (opt->json) std::cout << j.dump(2) << "\n";
        else std::cout << planText(session, opt->session.config, j);
        return 0;
    };
}

}  // namespace fp::cli
