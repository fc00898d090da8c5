#pragma once
// Executor: runs a Plan on one frame. Capture buffers are loaded at their first reader (not up
// front), every image is freed right after its last use, outputs are handed to the sink as soon
// as all their layers exist, and each pass's wall time and work counts go into the report.
#include "passes/core/Pass.h"
#include "passes/core/Planner.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace fp {

/// Where a frame's inputs come from (implemented by io/ for files, by tests in memory).
class FrameSource {
public:
    virtual ~FrameSource() = default;
    virtual FrameInfo frameInfo() = 0;
    /// Reads one capture buffer with `channels` channels at full resolution.
    virtual Texture loadBuffer(const std::string& buffer, int channels) = 0;
    virtual const RayScene& scene() = 0;
    virtual OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() = 0;
};

struct OutputLayer {
    std::string name;  //!< "pass.port" or the capture buffer name
    const Texture* texture;
    PortKind kind;
};

/// Where finished outputs go (io/ writes files; tests keep them).
class FrameSink {
public:
    virtual ~FrameSink() = default;
    virtual void write(const OutputDesc& output, const std::vector<OutputLayer>& layers,
                       const FrameInfo& frame) = 0;
};

struct PassReport {
    std::string name, type;
    double seconds = 0;
    std::map<std::string, uint64_t> work;
    std::map<std::string, double> metrics;  //!< what error_measure-like passes measured
};

struct FrameReport {
    int64_t frame = 0;
    double seconds = 0;
    std::vector<PassReport> passes;
    std::size_t peakBytes = 0;  //!< measured: most bytes of images held at once
    nlohmann::json toJson() const;
};

/// Called after each pass with (steps done, steps total) for progress lines.
using ProgressFn = std::function<void(int, int)>;

FrameReport executePlan(const Plan& plan, FrameSource& source, FrameSink& sink,
                        const ProgressFn& progress = {});

}  // namespace fp
