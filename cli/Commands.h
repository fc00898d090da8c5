#pragma once
// The subcommands of the framepass executable. Each registers its options on the CLI11 app and
// returns the process exit code when run; fp::Error escapes to main.cpp, the one place that maps
// errors to exit codes.
#include <CLI/CLI.hpp>

#include <functional>

namespace fp::cli {

using Command = std::function<int()>;

Command addBenchCommand(CLI::App& app);
Command addCaptureCommand(CLI::App& app);
Command addCompareCommand(CLI::App& app);
Command addCompletionCommand(CLI::App& app);
Command addInspectCommand(CLI::App& app);
Command addPassesCommand(CLI::App& app);
Command addPlanCommand(CLI::App& app);
Command addRunCommand(CLI::App& app);
Command addSheetCommand(CLI::App& app);
Command addTuneCommand(CLI::App& app);

}  // namespace fp::cli
