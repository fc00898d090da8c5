#pragma once
// Executor: runs a Plan on one frame. Capture buffers are loaded at their first reader (not up
// front), every image is freed right after its last use, outputs are handed to the sink as soon
// as all their layers exist, and each pass's wall time and work counts go into the report.
#include "framework/Pass.h"
#include "framework/Planner.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
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
    /// Seconds spent so far reading this frame's files (the bytes) and decoding them
    /// (decompression, conversion, the input checks): 0 for a frame held in memory.
    struct InputSeconds {
        double read = 0, decode = 0;
    };
    virtual InputSeconds inputSeconds() const { return {}; }
};

struct OutputLayer {
    std::string name;  //!< "pass.port" or the capture buffer name
    const Texture* texture;  //!< null when `device` holds the image instead
    PortKind kind;
    /// For a sink that takes images where they are (FrameSink::takesDeviceImages): the GPU's
    /// copy of an image a CUDA step made, shared, not copied (texture is then null).
    std::shared_ptr<const DeviceTexture> device = nullptr;
};

/// Where finished outputs go (io/ writes files; tests keep them).
class FrameSink {
public:
    virtual ~FrameSink() = default;
    /// Whether an image on the GPU is handed over there (OutputLayer::device) rather than
    /// brought to the host first: a door whose caller keeps working on the GPU.
    virtual bool takesDeviceImages() const { return false; }
    virtual void write(const OutputDesc& output,
                       const std::vector<OutputLayer>& layers,
                       const FrameInfo& frame) = 0;
};

struct PassReport {
    std::string name, type;
    double seconds = 0;                //!< wall time (on the GPU: launch to finish, host side)
    std::optional<double> gpuSeconds{};  //!< GPU steps: the kernels' time from CUDA events
    std::map<std::string, uint64_t> work{};
    std::map<std::string, double> metrics{};  //!< what error_measure-like passes measured
    /// Not executed: its outputs came from a StepCache (seconds is then 0; work and metrics are
    /// those of the run that made them).
    bool reused = false;
};

struct FrameReport {
    int64_t frame = 0;
    double seconds = 0;
    std::vector<PassReport> passes;
    std::size_t peakBytes = 0;  //!< measured: most bytes of images held at once
    std::size_t peakDeviceBytes = 0;  //!< the same in GPU memory (0 on the CPU)
    std::size_t uploadBytes = 0, downloadBytes = 0;  //!< what crossed between host and GPU
    double uploadSeconds = 0, downloadSeconds = 0;   //!< and how long each way took
    double transferSeconds() const { return uploadSeconds + downloadSeconds; }
    /// Steps executed and steps whose outputs a StepCache supplied.
    int executedSteps = 0, reusedSteps = 0;
    nlohmann::json toJson() const;
};

/// Called after each pass with (steps done, steps total, that pass's report: its time and work),
/// for progress and per-pass timing lines.
using ProgressFn = std::function<void(int, int, const PassReport&)>;

/// Temporal state carried between the frames of a sequence, owned by whoever runs the sequence.
/// Copies share the kept states: a copy taken before a frame is that frame's history again
/// (a look-dev session re-runs a frame after a change from the history it had).
class HistoryStore {
public:
    const PassHistory* find(const std::string& pass) const {
        auto it = mHistories.find(pass);
        return it == mHistories.end() ? nullptr : it->second.state.get();
    }
    /// What made the state `pass` kept ("" when none): part of the pass's next StepCache key.
    std::string signature(const std::string& pass) const {
        auto it = mHistories.find(pass);
        return it == mHistories.end() ? "" : it->second.signature;
    }
    void keep(const std::string& pass, PassHistory history, std::string signature = "") {
        keepShared(pass, std::make_shared<PassHistory>(std::move(history)), std::move(signature));
    }
    void keepShared(const std::string& pass, std::shared_ptr<PassHistory> history,
                    std::string signature) {
        mHistories[pass] = {std::move(history), std::move(signature)};
    }
    std::shared_ptr<PassHistory> shared(const std::string& pass) const {
        auto it = mHistories.find(pass);
        return it == mHistories.end() ? nullptr : it->second.state;
    }
    void clear() { mHistories.clear(); }
    /// The history of `pass` with its state copied to `device` if it is only on the other side
    /// (nullptr if there is none).
    const PassHistory* placeOn(const std::string& pass, Device device);

private:
    struct Kept {
        std::shared_ptr<PassHistory> state;
        std::string signature;
    };
    std::map<std::string, Kept> mHistories;
};

/// The outputs of a plan's steps kept from one run to the next: the incremental re-run of a
/// look-dev session. A step whose key matches its last run's, and which made then every output
/// asked of it now, is not executed; the outputs it made then are used again. The key is the
/// pass type, device, parameters, the frame and, recursively, the keys of everything it reads
/// (capture buffers by `sourceId` and frame, upstream steps by their keys, a temporal pass's
/// history by what made it), so a change re-runs exactly the steps downstream of it, and asking
/// for one more output re-runs only the step that makes it.
class StepCache {
public:
    /// Names the capture the frames come from; a different capture is a different key.
    std::string sourceId;
    void clear() {
        mEntries.clear();
        mCaptures.clear();
    }
    std::size_t size() const { return mEntries.size(); }

private:
    friend FrameReport executePlan(const Plan&, FrameSource&, FrameSink&, const ProgressFn&,
                                   HistoryStore*, StepCache*);
    struct Entry {
        std::string key;
        std::map<std::string, std::shared_ptr<Texture>> host;
        std::map<std::string, std::shared_ptr<DeviceTexture>> device;
        PassReport report;
        std::shared_ptr<PassHistory> kept;
    };
    std::map<std::string, Entry> mEntries;  //!< by step name
    /// The capture buffers the last run read ("capture:Buffer/channels"), on the host and, once
    /// a GPU step read them, on the GPU: a re-run of the same frame neither reads nor uploads
    /// them again. Only the last frame's are kept (`mCapturesOf`: source and frame).
    std::string mCapturesOf;
    std::map<std::string, std::pair<std::shared_ptr<Texture>, std::shared_ptr<DeviceTexture>>>
        mCaptures;
};

/// A camera cut: this frame's previous camera is not the camera the history was made with.
/// (Without a previous camera in the capture, the history's own camera is trusted.)
bool isCameraCut(const CameraView& historyCamera, const FrameCamera& frame);

/// Runs one frame. Temporal passes read and update `history` when given (a sequence); without
/// it every frame is a first frame. With `cache`, steps unchanged since the cache's last run
/// are not executed (StepCache).
FrameReport executePlan(const Plan& plan,
                        FrameSource& source,
                        FrameSink& sink,
                        const ProgressFn& progress = {},
                        HistoryStore* history = nullptr,
                        StepCache* cache = nullptr);

}  // namespace fp
