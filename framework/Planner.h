#pragma once
// Planner: config → Plan, pure and pixel-free (architecture anchors B5). Its stages, in order
// (makePlan lists them): expand the light templates, validate names and cvars, instantiate every
// pass from its parameters, bind inputs, bind the requested outputs as roots, cull what no root
// needs, check what live passes need, order topologically (declaration order breaks ties), then
// compute each step's outputs, when each image can be freed, and exactly which capture buffers,
// lights, geometry and colour config the frame needs.
#include "framework/ChainTemplate.h"
#include "framework/Diagnostics.h"
#include "framework/GraphDesc.h"
#include "framework/Pass.h"
#include "framework/PassRegistry.h"

#include <nlohmann/json.hpp>

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace fp {

/// Where an input comes from: a capture buffer or another pass's output.
struct SourceRef {
    bool fromCapture = false;
    std::string buffer;  //!< capture buffer name when fromCapture
    int step = -1;       //!< producing step otherwise
    std::string port;    //!< producing port
    std::string key;     //!< "capture:Buffer" or "pass.port"
    PortKind kind = PortKind::Data;
    int channels = 0;
};

struct PlanStep {
    std::string name, type, pointer;
    std::shared_ptr<Pass> pass;
    PassIO io;
    nlohmann::json params;                    //!< resolved parameter values
    std::map<std::string, SourceRef> inputs;  //!< bound input ports
    /// Unbound optional ports read from this capture buffer on a frame with no previous camera.
    std::map<std::string, std::string> noPreviousCameraInputs;
    std::set<std::string> requestedOutputs;
    Device device = Device::Cpu;  //!< Cuda where the plan asks for the GPU and the pass has a kernel
    /// The parameters the config's params or a set fixed, each with where (a JSON pointer or the
    /// door's name of the setting): a cvar of one of them has no effect on this pass.
    std::map<std::string, std::string> pinned;
};

struct CulledPass {
    std::string name, type, reason;
};

struct CaptureRead {
    std::string buffer;
    int channels = 0;
    PortKind kind = PortKind::Data;
};

struct Plan {
    std::vector<PlanStep> steps;  //!< live passes in execution order
    Device device = Device::Cpu;  //!< what the config or --device asked for
    std::vector<CulledPass> culled;
    std::vector<OutputDesc> outputs;        //!< files to write, dumps included
    std::vector<CaptureRead> captureReads;  //!< capture buffers the live passes read
    bool needsCamera = false, needsScene = false, needsColorConfig = false;
    bool needsLights = false;                 //!< the scene's lights (not its geometry) are read
    std::vector<ExpandedTemplate> templates;  //!< the light templates and what they became
    std::vector<Diagnostic> warnings;
    /// Key ("pass.port" / "capture:X") → last step after which it is no longer needed (read or
    /// written out). Images are freed right after that step.
    std::map<std::string, int> releaseAfter;
    /// Step → indices into `outputs` that are complete after it.
    std::map<int, std::vector<int>> writesAfter;
    /// Step → capture buffers first read by it (loaded just before it runs).
    std::map<int, std::vector<std::string>> loadsBefore;
    /// Output source key → colour or data, as resolved when the outputs were bound.
    std::map<std::string, PortKind> outputKinds;

    /// The host memory a frame of `frame` pixels takes at its peak: the images held at once
    /// (capture reads, outputs with their mips and row padding), the scratch of the step running
    /// then (its outputs nobody reads included: they are freed after it) and the histories kept
    /// across frames.
    struct MemoryEstimate {
        std::size_t images = 0;   //!< held at the peak step
        std::size_t scratch = 0;  //!< of the peak step
        std::size_t history = 0;  //!< the temporal passes' kept states at the peak step
        std::string peakStep;     //!< where the peak is ("" with no steps)
        std::size_t peak() const { return images + scratch + history; }
    };
    /// `preread`: the frame's capture buffers were read before it started (a run reading ahead),
    /// so each is held from the first step, not from the step that first reads it. `sequence`:
    /// a frame after the first, which starts with every temporal pass's history; the first holds
    /// only the histories its earlier steps kept.
    MemoryEstimate estimateMemory(Extent frame, bool preread = false, bool sequence = false) const;
    std::size_t estimatePeakBytes(Extent frame) const { return estimateMemory(frame).peak(); }
    nlohmann::json toJson(Extent frame) const;
};

struct PlanInputs {
    PlanOverrides overrides;
    /// Capture buffers the file has (from its header); absent = not checked.
    std::optional<std::set<std::string>> availableBuffers;
    /// Channel counts of the capture's Truth.* layers (1 = Y, 3 = RGB), from its header.
    std::map<std::string, int> truthChannels;
    /// The scene's lights, in order: each light template is expanded once per light.
    std::vector<std::string> lightNames;
    /// Problems already found (by the config loader), reported together with the planner's.
    std::vector<Diagnostic> priorErrors;
    /// A cvar framepass does not know is a warning instead of an error (--allow-unknown-cvars).
    bool allowUnknownCvars = false;
};

/// Builds the plan; throws fp::UsageError listing every problem when the config is invalid.
Plan makePlan(const GraphDesc& graph, const PassRegistry& registry, const PlanInputs& inputs);

}  // namespace fp
