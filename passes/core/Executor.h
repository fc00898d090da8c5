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
#include <optional>
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
    /// The scene's lights; unlike scene(), this reads no geometry.
    virtual const std::vector<Light>& lights() = 0;
    /// The scene's sky light; empty (not an error) when there is no scene.
    virtual const Environment& environment() = 0;
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
    virtual void write(const OutputDesc& output,
                       const std::vector<OutputLayer>& layers,
                       const FrameInfo& frame) = 0;
};

struct PassReport {
    std::string name, type;
    double seconds = 0;                //!< wall time (on the GPU: launch to finish, host side)
    std::optional<double> gpuSeconds;  //!< GPU steps: the kernels' time from CUDA events
    std::map<std::string, uint64_t> work;
    std::map<std::string, double> metrics;  //!< what error_measure-like passes measured
};

struct FrameReport {
    int64_t frame = 0;
    double seconds = 0;
    std::vector<PassReport> passes;
    std::size_t peakBytes = 0;  //!< measured: most bytes of images held at once
    std::size_t peakDeviceBytes = 0;  //!< the same in GPU memory (0 on the CPU)
    std::size_t uploadBytes = 0, downloadBytes = 0;  //!< what crossed between host and GPU
    double transferSeconds = 0;
    nlohmann::json toJson() const;
};

/// Temporal state carried between the frames of a sequence, owned by whoever runs the sequence.
class HistoryStore {
public:
    const PassHistory* find(const std::string& pass) const {
        auto it = mHistories.find(pass);
        return it == mHistories.end() ? nullptr : &it->second;
    }
    void keep(const std::string& pass, PassHistory history) {
        mHistories[pass] = std::move(history);
    }
    void clear() { mHistories.clear(); }
    /// The history of `pass` with its state copied to `device` if it is only on the other side
    /// (nullptr if there is none).
    const PassHistory* placeOn(const std::string& pass, Device device);

private:
    std::map<std::string, PassHistory> mHistories;
};

/// A camera cut: this frame's previous camera is not the camera the history was made with.
/// (Without a previous camera in the capture, the history's own camera is trusted.)
bool isCameraCut(const CameraView& historyCamera, const FrameCamera& frame);

/// Called after each pass with (steps done, steps total, that pass's report: its time and work),
/// for progress and per-pass timing lines.
using ProgressFn = std::function<void(int, int, const PassReport&)>;

/// Runs one frame. Temporal passes read and update `history` when given (a sequence); without
/// it every frame is a first frame.
FrameReport executePlan(const Plan& plan,
                        FrameSource& source,
                        FrameSink& sink,
                        const ProgressFn& progress = {},
                        HistoryStore* history = nullptr);

}  // namespace fp
