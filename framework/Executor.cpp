#include "framework/Executor.h"

#include "foundation/Scene.h"
#include "framework/SemanticBuffers.h"

#include "foundation/Cuda.h"
#include "foundation/Error.h"

#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>

namespace fp {

namespace {

// The store of images alive during one frame, keyed "pass.port" or "capture:Buffer". An image
// may live on the host, on the GPU or both: it is copied across only when a step on the other
// side (or the sink) reads it, so a chain of GPU passes keeps its images resident.
class ImageStore {
public:
    using KeptCaptures =
        std::map<std::string, std::pair<std::shared_ptr<Texture>, std::shared_ptr<DeviceTexture>>>;

    /// `kept`: a StepCache's capture buffers of this frame, used instead of loading (and
    /// uploading) them again, and given every buffer this run loads or uploads.
    ImageStore(FrameSource& source, KeptCaptures* kept) : mSource(source), mKept(kept) {}
    ~ImageStore() {
        for (const auto& [key, slot] : mSlots)
            keep(key, slot);
    }

    /// Reads capture buffer `buffer` (with `channels`) unless the store holds it already.
    void load(const std::string& buffer, int channels) {
        const std::string key = "capture:" + buffer;
        if (contains(key))
            return;
        if (mKept)
            if (auto it = mKept->find(keptName(key, channels)); it != mKept->end()) {
                adopt(key, it->second.first, it->second.second);
                mChannels[key] = channels;
                return;
            }
        put(key, mSource.loadBuffer(buffer, channels));
        mChannels[key] = channels;
    }
    Texture& put(const std::string& key, Texture t) {
        Slot& slot = mSlots[key] = Slot{};
        slot.host = std::make_shared<Texture>(std::move(t));
        track();
        return *slot.host;
    }
    DeviceTexture& putDevice(const std::string& key, DeviceTexture t) {
        Slot& slot = mSlots[key] = Slot{};
        slot.device = std::make_shared<DeviceTexture>(std::move(t));
        track();
        return *slot.device;
    }
    /// Puts images a StepCache kept (shared, not copied).
    void adopt(const std::string& key, std::shared_ptr<Texture> host,
               std::shared_ptr<DeviceTexture> device) {
        mSlots[key] = Slot{std::move(host), std::move(device)};
        track();
    }
    /// The images under `key`, shared (for a StepCache).
    std::pair<std::shared_ptr<Texture>, std::shared_ptr<DeviceTexture>> shared(
        const std::string& key) const {
        auto it = mSlots.find(key);
        if (it == mSlots.end()) return {};
        return {it->second.host, it->second.device};
    }
    bool contains(const std::string& key) const { return mSlots.count(key) > 0; }
    /// The host copy (downloaded from the GPU on first use); nullptr if the key is unknown.
    const Texture* find(const std::string& key) {
        auto it = mSlots.find(key);
        if (it == mSlots.end())
            return nullptr;
        Slot& slot = it->second;
        if (!slot.host) {
            slot.host = std::make_shared<Texture>(cuda::download(*slot.device));
            track();
        }
        return slot.host.get();
    }
    /// The device copy (uploaded on first use); nullptr if the key is unknown.
    const DeviceTexture* findDevice(const std::string& key) {
        auto it = mSlots.find(key);
        if (it == mSlots.end())
            return nullptr;
        Slot& slot = it->second;
        if (!slot.device) {
            slot.device = std::make_shared<DeviceTexture>(cuda::upload(*slot.host));
            track();
        }
        return slot.device.get();
    }
    /// Starts the device copy of a host image (cuda::uploadAsync) unless it has one.
    void prefetchDevice(const std::string& key) {
        auto it = mSlots.find(key);
        if (it == mSlots.end() || it->second.device)
            return;
        it->second.device = std::make_shared<DeviceTexture>(cuda::uploadAsync(*it->second.host));
        track();
    }
    void release(const std::string& key) {
        if (auto it = mSlots.find(key); it != mSlots.end()) {
            keep(key, it->second);
            mSlots.erase(it);
        }
    }
    std::size_t peak() const { return mPeak; }
    std::size_t peakDevice() const { return mPeakDevice; }

private:
    // An image on the host, on the GPU or both (null where it is not). Shared with a StepCache
    // when there is one, so a kept output is never copied.
    struct Slot {
        std::shared_ptr<Texture> host;
        std::shared_ptr<DeviceTexture> device;
    };
    void track() {
        std::size_t host = 0, device = 0;
        for (const auto& [k, slot] : mSlots) {
            host += slot.host ? slot.host->bytes() : 0;
            device += slot.device ? slot.device->bytes() : 0;
        }
        mPeak = std::max(mPeak, host);
        mPeakDevice = std::max(mPeakDevice, device);
    }
    static std::string keptName(const std::string& key, int channels) {
        return fmt::format("{}/{}", key, channels);
    }
    // A capture buffer handed to the StepCache as it leaves the store (its device copy included
    // when a GPU step made one).
    void keep(const std::string& key, const Slot& slot) {
        auto channels = mChannels.find(key);
        if (mKept && channels != mChannels.end())
            (*mKept)[keptName(key, channels->second)] = {slot.host, slot.device};
    }
    FrameSource& mSource;
    KeptCaptures* mKept;
    std::map<std::string, Slot> mSlots;
    std::map<std::string, int> mChannels;  //!< the capture buffers loaded, with their channels
    std::size_t mPeak = 0, mPeakDevice = 0;
};

class StepContext final : public PassContext {
public:
    StepContext(const PlanStep& step,
                ImageStore& store,
                FrameSource& source,
                const FrameInfo& frame,
                PassReport& report,
                const PassHistory* history)
        : mStep(step),
          mStore(store),
          mSource(source),
          mFrame(frame),
          mReport(report),
          mHistory(history) {}

    const PassHistory* history() const override {
        requireTemporal("reads");
        return mHistory;
    }
    void keepHistory(Texture state) override {
        requireTemporal("keeps");
        mKept = PassHistory{std::move(state), {}, mFrame.camera.current};
    }
    void keepHistory(DeviceTexture state) override {
        requireTemporal("keeps");
        mKept = PassHistory{{}, std::move(state), mFrame.camera.current};
    }
    /// The state the pass kept this frame, if any.
    std::optional<PassHistory>& kept() { return mKept; }

    const Texture* input(std::string_view port) const override {
        const std::string key = storeKey(port);
        if (key.empty())
            return nullptr;  // unbound optional input
        const Texture* t = mStore.find(key);
        FP_CHECK(t, "internal: input '{}' of pass '{}' is not in the store", port, mStep.name);
        return t;
    }
    const DeviceTexture* deviceInput(std::string_view port) override {
        const std::string key = storeKey(port);
        if (key.empty())
            return nullptr;
        const DeviceTexture* t = mStore.findDevice(key);
        FP_CHECK(t, "internal: input '{}' of pass '{}' is not in the store", port, mStep.name);
        return t;
    }
    PortKind inputKind(std::string_view port) const override {
        auto it = mStep.inputs.find(std::string(port));
        return it == mStep.inputs.end() ? PortKind::Data : it->second.kind;
    }
    bool isRequested(std::string_view port) const override {
        return mStep.requestedOutputs.count(std::string(port)) > 0;
    }
    Texture& output(std::string_view port, const std::vector<Extent>& mips,
                    bool zeroed) override {
        const PortSpec& spec = checkDeclared(mStep.io.outputs, port, "output");
        std::vector<Image> levels;
        for (const Extent& e : mips)
            levels.push_back(zeroed ? Image(e.width, e.height, spec.channels)
                                    : Image(e.width, e.height, spec.channels, Image::Uncleared{}));
        return mStore.put(mStep.name + "." + std::string(port), Texture(std::move(levels)));
    }
    DeviceTexture& deviceOutput(std::string_view port, const std::vector<Extent>& mips,
                                bool zeroed) override {
        const PortSpec& spec = checkDeclared(mStep.io.outputs, port, "output");
        return mStore.putDevice(mStep.name + "." + std::string(port),
                                cuda::allocate(mips, spec.channels, zeroed));
    }
    const FrameInfo& frame() const override { return mFrame; }
    const RayScene& scene() override {
        FP_CHECK(mStep.io.needsScene, "pass '{}' uses the scene without declaring needsScene",
                 mStep.name);
        return mSource.scene();
    }
    const std::vector<Light>& lights() override {
        FP_CHECK(mStep.io.needsLights || mStep.io.needsScene,
                 "pass '{}' reads the lights without declaring needsLights", mStep.name);
        return mSource.lights();
    }
    const Environment& environment() override {
        FP_CHECK(mStep.io.needsEnvironment,
                 "pass '{}' reads the environment without declaring needsEnvironment", mStep.name);
        return mSource.environment();
    }
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() override { return mSource.colorConfig(); }
    void addWork(std::string_view counter, uint64_t amount) override {
        std::lock_guard<std::mutex> lock(mMutex);
        mReport.work[std::string(counter)] += amount;
    }
    void addMetric(std::string_view name, double value) override {
        std::lock_guard<std::mutex> lock(mMutex);
        mReport.metrics[std::string(name)] = value;
    }

private:
    // Filament's rule again: only a pass that declared itself temporal has a history.
    void requireTemporal(const char* verb) const {
        FP_CHECK(mStep.io.temporal, "pass '{}' {} history without declaring temporal", mStep.name,
                 verb);
    }
    // The store key of an input port: the one bound to it or, for an unbound port the plan fills
    // from the capture on a frame with no previous camera (PortSpec::captureWhenNoPreviousCamera),
    // that buffer's (loaded on first use); "" for an unbound optional input.
    std::string storeKey(std::string_view port) const {
        if (auto it = mStep.inputs.find(std::string(port)); it != mStep.inputs.end())
            return it->second.key;
        checkDeclared(mStep.io.inputs, port, "input");
        if (mFrame.camera.previous) return "";
        auto it = mStep.noPreviousCameraInputs.find(std::string(port));
        if (it == mStep.noPreviousCameraInputs.end()) return "";
        const SemanticBuffer* sem = findSemanticBuffer(it->second);
        mStore.load(it->second, sem ? int(sem->channels.size()) : 1);
        return "capture:" + it->second;
    }
    // Filament's rule: a pass may only touch what it declared.
    const PortSpec& checkDeclared(const std::vector<PortSpec>& ports,
                                  std::string_view port,
                                  const char* what) const {
        for (const auto& p : ports)
            if (p.name == port)
                return p;
        throw Error(fmt::format("pass '{}' used undeclared {} '{}'", mStep.name, what, port));
    }

    const PlanStep& mStep;
    ImageStore& mStore;
    FrameSource& mSource;
    const FrameInfo& mFrame;
    PassReport& mReport;
    const PassHistory* mHistory;
    std::optional<PassHistory> mKept;
    std::mutex mMutex;
};

// A step's StepCache key: what it is, how it is set, the frame, and the keys of what it reads
// (StepCache says why each is there). Which of its outputs are asked for is not in it: an
// output's bits do not depend on which others were asked for, so a step that made more than is
// asked now is reused, and asking for another output re-runs that step alone.
std::string stepKey(const PlanStep& step, const std::vector<std::string>& stepKeys,
                    const FrameInfo& frame, const std::string& sourceId,
                    const std::string& historyKey) {
    std::string key = fmt::format("{}|{}|{}|{}#{}", step.type, int(step.device),
                                  step.params.dump(), sourceId, frame.number);
    for (const auto& [port, ref] : step.inputs)
        key += "|" + port + "=" +
               (ref.fromCapture ? ref.key : ref.port + "@" + stepKeys[std::size_t(ref.step)]);
    if (step.io.temporal)
        key += "|history=" + (frame.firstInSequence ? std::string("none") : historyKey);
    // Long chains nest keys: keep each to a fixed size.
    return fmt::format("{:016x}", std::hash<std::string>{}(key));
}

}  // namespace

const PassHistory* HistoryStore::placeOn(const std::string& pass, Device device) {
    auto it = mHistories.find(pass);
    if (it == mHistories.end())
        return nullptr;
    // The copy across is added beside the state (copies of the store share it, and see it too).
    PassHistory& h = *it->second.state;
    if (device == Device::Cuda && h.deviceState.empty() && !h.state.empty())
        h.deviceState = cuda::upload(h.state);
    if (device == Device::Cpu && h.state.empty() && !h.deviceState.empty())
        h.state = cuda::download(h.deviceState);
    return &h;
}

bool isCameraCut(const CameraView& h, const FrameCamera& frame) {
    if (!frame.previous)
        return false;
    const CameraView& p = *frame.previous;
    // Cameras read back from files carry rounding: allow a relative 1e-5 of the distance from the
    // origin (plus 1e-5 units), and direction cosines within 1e-6.
    const Vec3d d = h.position - p.position;
    const double scale = 1e-5 * (1.0 + std::sqrt(dot(p.position, p.position)));
    return dot(d, d) > scale * scale || dot(h.forward, p.forward) < 1.0 - 1e-6 ||
           dot(h.up, p.up) < 1.0 - 1e-6 || std::fabs(h.fx - p.fx) > 1e-6 * std::fabs(p.fx) ||
           h.width != p.width || h.height != p.height;
}

FrameReport executePlan(const Plan& plan,
                        FrameSource& source,
                        FrameSink& sink,
                        const ProgressFn& progress,
                        HistoryStore* history,
                        StepCache* cache) {
    using Clock = std::chrono::steady_clock;
    const auto frameStart = Clock::now();
    if (plan.device == Device::Cuda) {
        if (const std::string why = cuda::unavailableReason(); !why.empty())
            throw UsageError(fmt::format("--device cuda: {}", why));
        cuda::usePinnedHostMemory();  // the capture is read into memory the GPU copies fastest
    }
    const cuda::TransferTotals transfersBefore = cuda::transferTotals();
    const FrameInfo frame = source.frameInfo();
    FrameReport report;
    report.frame = frame.number;
    ImageStore::KeptCaptures* keptCaptures = nullptr;
    if (cache) {
        const std::string capturesOf = fmt::format("{}#{}", cache->sourceId, frame.number);
        if (cache->mCapturesOf != capturesOf) {
            cache->mCaptures.clear();
            cache->mCapturesOf = capturesOf;
        }
        keptCaptures = &cache->mCaptures;
    }
    ImageStore store(source, keptCaptures);
    // Copies still crossing to the GPU are waited for before the store frees their images, also
    // when a pass throws: a freed block would go back to the memory pools mid-copy.
    struct UploadsFinished {
        bool gpu;
        ~UploadsFinished() {
            if (!gpu) return;
            try {
                cuda::finishUploads();
            } catch (const std::exception&) {
                // Already failing (the GPU's error surfaces again on its next call).
            }
        }
    } uploadsFinished{plan.device == Device::Cuda};
    if (history && frame.firstInSequence)
        history->clear();

    auto channelsOf = [&](const std::string& buffer) {
        for (const auto& r : plan.captureReads)
            if (r.buffer == buffer)
                return r.channels;
        return 0;
    };
    auto writeOutputs = [&](int step) {
        auto it = plan.writesAfter.find(step);
        if (it == plan.writesAfter.end())
            return;
        for (int o : it->second) {
            const OutputDesc& out = plan.outputs[o];
            std::vector<OutputLayer> layers;
            for (const auto& src : out.sources) {
                const bool capture = src.rfind("capture:", 0) == 0;
                if (capture)
                    store.load(src.substr(8), channelsOf(src.substr(8)));
                if (!capture && sink.takesDeviceImages())
                    if (auto device = store.shared(src).second) {
                        layers.push_back({src, nullptr, plan.outputKinds.at(src), device});
                        continue;
                    }
                const Texture* t = store.find(src);
                FP_CHECK(t && !t->empty(), "frame {}: '{}' was not produced by its pass",
                         frame.number, src);
                layers.push_back({capture ? src.substr(8) : src, t, plan.outputKinds.at(src)});
            }
            sink.write(out, layers, frame);
        }
    };
    auto releaseAfter = [&](int step) {
        for (const auto& [key, last] : plan.releaseAfter)
            if (last == step)
                store.release(key);
    };

    // A GPU plan reads the capture buffers its GPU steps take up front and starts their copies to
    // the GPU on the upload stream in the order the steps need them: the first passes run while
    // the rest of the capture crosses (each step's kernels wait for their own inputs only).
    if (plan.device == Device::Cuda)
        for (const PlanStep& step : plan.steps) {
            if (step.device != Device::Cuda)
                continue;
            for (const auto& [port, ref] : step.inputs) {
                if (!ref.fromCapture)
                    continue;
                store.load(ref.buffer, channelsOf(ref.buffer));
                store.prefetchDevice(ref.key);
            }
        }

    const int total = int(plan.steps.size());
    // What every step ends with, executed or reused: its report, the files it completes, the
    // images no later step reads freed, progress.
    auto finishStep = [&](int s, PassReport pr) {
        report.passes.push_back(std::move(pr));
        writeOutputs(s);
        releaseAfter(s);
        // Outputs the pass wrote though nobody reads them (a StepCache keeps its own share).
        for (const auto& port : plan.steps[std::size_t(s)].io.outputs)
            if (!plan.steps[std::size_t(s)].requestedOutputs.count(port.name))
                store.release(plan.steps[std::size_t(s)].name + "." + port.name);
        if (progress)
            progress(s + 1, total, report.passes.back());
    };
    std::vector<std::string> stepKeys(plan.steps.size());
    if (cache)  // steps the plan no longer has are forgotten
        std::erase_if(cache->mEntries, [&](const auto& entry) {
            return std::none_of(plan.steps.begin(), plan.steps.end(),
                                [&](const PlanStep& st) { return st.name == entry.first; });
        });
    for (int s = 0; s < total; ++s) {
        const PlanStep& step = plan.steps[s];
        if (auto it = plan.loadsBefore.find(s); it != plan.loadsBefore.end())
            for (const auto& b : it->second)
                store.load(b, channelsOf(b));
        PassReport pr{.name = step.name, .type = step.type};
        if (cache) {
            stepKeys[std::size_t(s)] = stepKey(step, stepKeys, frame, cache->sourceId,
                                               history ? history->signature(step.name) : "");
            auto hit = cache->mEntries.find(step.name);
            auto made = [&](const std::string& port) {
                const std::string key = step.name + "." + port;
                return hit->second.host.count(key) > 0 || hit->second.device.count(key) > 0;
            };
            if (hit != cache->mEntries.end() && hit->second.key == stepKeys[std::size_t(s)] &&
                std::all_of(step.requestedOutputs.begin(), step.requestedOutputs.end(), made)) {
                // Unchanged since the cache's run: its outputs (and the history it kept then)
                // stand, nothing is executed.
                const StepCache::Entry& e = hit->second;
                for (const auto& port : step.io.outputs) {
                    const std::string key = step.name + "." + port.name;
                    auto h = e.host.find(key);
                    auto d = e.device.find(key);
                    if (h != e.host.end() || d != e.device.end())
                        store.adopt(key, h != e.host.end() ? h->second : nullptr,
                                    d != e.device.end() ? d->second : nullptr);
                }
                if (history && e.kept)
                    history->keepShared(step.name, e.kept, e.key);
                pr = e.report;
                pr.seconds = 0;
                pr.gpuSeconds.reset();
                pr.reused = true;
                ++report.reusedSteps;
                finishStep(s, std::move(pr));
                continue;
            }
        }
        const PassHistory* past = nullptr;
        if (history && step.io.temporal && !frame.firstInSequence) {
            past = history->find(step.name);
            if (past && isCameraCut(past->camera, frame.camera))
                past = nullptr;
            if (past)
                past = history->placeOn(step.name, step.device);
        }
        StepContext ctx(step, store, source, frame, pr, past);
        std::optional<cuda::EventTimer> gpuTimer;
        try {
            if (step.device == Device::Cuda) {
                // Inputs cross before the clock starts: the GPU time is the kernels' alone.
                for (const auto& [port, ref] : step.inputs)
                    if (const DeviceTexture* d = store.findDevice(ref.key))
                        cuda::awaitUpload(*d);
                gpuTimer.emplace();
                gpuTimer->start();
            }
        } catch (const Error& e) {
            throw Error(fmt::format("frame {}: pass '{}' ({}): {}", frame.number, step.name,
                                    step.type, e.what()),
                        e.code());
        }
        const auto t0 = Clock::now();
        try {
            if (step.device == Device::Cuda) {
                step.pass->executeCuda(ctx);
                gpuTimer->stop();
                pr.gpuSeconds = gpuTimer->seconds();
            } else {
                step.pass->execute(ctx);
            }
        } catch (const Error& e) {
            throw Error(fmt::format("frame {}: pass '{}' ({}): {}", frame.number, step.name,
                                    step.type, e.what()),
                        e.code());
        }
        pr.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        std::shared_ptr<PassHistory> kept;
        if (history && ctx.kept()) {
            kept = std::make_shared<PassHistory>(std::move(*ctx.kept()));
            history->keepShared(step.name, kept, cache ? stepKeys[std::size_t(s)] : "");
        }
        for (const auto& port : step.requestedOutputs)
            FP_CHECK(store.contains(step.name + "." + port),
                     "frame {}: pass '{}' did not write its "
                     "requested output '{}'",
                     frame.number, step.name, port);
        ++report.executedSteps;
        if (cache) {
            StepCache::Entry& e = cache->mEntries[step.name];
            e = {stepKeys[std::size_t(s)], {}, {}, pr, kept};
            for (const auto& port : step.io.outputs) {
                const std::string key = step.name + "." + port.name;
                auto [host, device] = store.shared(key);
                if (host) e.host[key] = host;
                if (device) e.device[key] = device;
            }
        }
        finishStep(s, std::move(pr));
    }
    writeOutputs(-1);  // outputs that only copy capture buffers, in a plan with no steps
    if (plan.device == Device::Cuda)
        cuda::finishUploads();  // the upload time is booked before the report reads it
    report.peakBytes = store.peak();
    report.peakDeviceBytes = store.peakDevice();
    const cuda::TransferTotals transfersAfter = cuda::transferTotals();
    report.uploadBytes = transfersAfter.uploadBytes - transfersBefore.uploadBytes;
    report.downloadBytes = transfersAfter.downloadBytes - transfersBefore.downloadBytes;
    report.uploadSeconds = transfersAfter.uploadSeconds - transfersBefore.uploadSeconds;
    report.downloadSeconds = transfersAfter.downloadSeconds - transfersBefore.downloadSeconds;
    report.seconds = std::chrono::duration<double>(Clock::now() - frameStart).count();
    return report;
}

nlohmann::json FrameReport::toJson() const {
    nlohmann::json j = {{"frame", frame}, {"seconds", seconds}, {"peakBytes", peakBytes}};
    if (peakDeviceBytes > 0 || uploadBytes > 0) {
        j["peakDeviceBytes"] = peakDeviceBytes;
        j["transfers"] = {{"uploadBytes", uploadBytes},
                          {"downloadBytes", downloadBytes},
                          {"uploadSeconds", uploadSeconds},
                          {"downloadSeconds", downloadSeconds},
                          {"seconds", transferSeconds()}};
    }
    j["passes"] = nlohmann::json::array();
    for (const auto& p : passes) {
        nlohmann::json pj = {
            {"name", p.name}, {"type", p.type}, {"seconds", p.seconds}, {"work", p.work}};
        if (p.gpuSeconds) {
            pj["device"] = "cuda";
            pj["gpuSeconds"] = *p.gpuSeconds;
        }
        if (p.reused)
            pj["reused"] = true;
        if (!p.metrics.empty())
            pj["metrics"] = p.metrics;
        j["passes"].push_back(pj);
    }
    return j;
}

}  // namespace fp
