#pragma once
// The subcommands of the framepass executable. Each registers its options on the CLI11 app and
// returns the process exit code when run; fp::Error escapes to main.cpp, the one place that maps
// errors to exit codes.
#include "app/Invocation.h"

#include <CLI/CLI.hpp>

#include <functional>

namespace fp::cli {

// The commands are doors onto the application library: its names read unqualified here.
using namespace fp::app;

using Command = std::function<int()>;

Command addBenchCommand(CLI::App& app);
Command addCaptureCommand(CLI::App& app);
Command addCompareCommand(CLI::App& app);
Command addCompletionCommand(CLI::App& app);
Command addInspectCommand(CLI::App& app);
Command addPassesCommand(CLI::App& app);
Command addPlanCommand(CLI::App& app);
Command addRunCommand(CLI::App& app);
Command addSchemaCommand(CLI::App& app);
Command addServeCommand(CLI::App& app);
Command addSheetCommand(CLI::App& app);
Command addTuneCommand(CLI::App& app);

/// SIGTERM and SIGINT no longer end the process at once: the first asks the application to stop
/// at its next safe point (app::requestStop); a second ends the process at once.
void catchStopSignals();

}  // namespace fp::cli
