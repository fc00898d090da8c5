#pragma once
// Flags that several subcommands share. Each fills an option struct of the application library
// (app/), which does the work; only their spelling and help text live here.
#include "app/BenchSweep.h"
#include "app/RunSetup.h"

#include <CLI/CLI.hpp>

#include <string>

namespace fp::cli {

/// A path option's check: an empty value names no file (`-o ''` would write into the working
/// folder, `--report ''` would be ignored), so it is a usage error.
const CLI::Validator& nonEmptyPath();

/// The config argument, --cvar, --cvars, --set, --dump, --frames, --capture, --previous,
/// --profile, --device and --allow-unknown-cvars.
void addSetupOptions(CLI::App& sub, app::SetupOptions& options);
/// --sweep NAME=V1,V2,... or NAME=A..B (repeatable: a grid), each read into a typed axis.
void addSweepOption(CLI::App& sub, std::vector<app::SweepAxis>& axes, const std::string& help);
/// --runs and --warmup (their help names the current defaults) on bench or tune.
void addTimingOptions(CLI::App& sub, app::BenchOptions& options);
/// --decompose-rays, bounded by what the converged tracer can trace (bench, tune, run).
void addDecomposeRaysOption(CLI::App& sub, int& rays, const std::string& help);
/// --max-memory (text kept in `value`; app/MemoryLimit.h reads it).
void addMaxMemoryOption(CLI::App& sub, std::string& value);

}  // namespace fp::cli
