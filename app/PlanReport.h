#pragma once
// `framepass plan`: the resolved chain of a setup, without reading a pixel — as JSON, as the
// table `plan` prints, and as a Graphviz graph.
#include "app/RunSetup.h"

#include <nlohmann/json.hpp>

#include <string>

namespace fp::app {

/// The plan with the config (`config`: as the user named it), capture, frames and profile, and each capture read's channels
/// (the capture's header is read when it is on disk; `captureOnDisk` says whether it is, and a
/// warning says what that leaves unchecked). `plan --json` prints it.
nlohmann::json planJson(const RunSetup& session, const std::string& config);
/// The table `plan` prints for planJson's `j`.
std::string planText(const RunSetup& session, const std::string& config,
                     const nlohmann::json& j);
/// The resolved chain as a Graphviz graph: capture buffers, passes (blue on the CPU, green on the
/// GPU) with their ports, the files written, and culled passes greyed with why.
std::string planDot(const Plan& plan);

/// The steps `source` depends on: the step that makes it and every step upstream of that, in
/// execution order, leaving out steps that measure errors (a method's own passes: what bench and
/// the workbench pair an error with). Empty for a capture buffer.
std::vector<int> upstreamSteps(const Plan& plan, const SourceRef& source);

}  // namespace fp::app
