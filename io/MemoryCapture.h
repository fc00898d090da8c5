#pragma once
// A capture held in memory instead of in files: the canonical buffers (SceneDepth, WorldNormal,
// BaseColor, … as docs/captures.md names them) and Truth.* layers as images, with the frame's
// camera and number. The Python module makes one from numpy arrays (Capture.from_arrays) or by
// reading a capture through its profile (read_capture); a Session runs on it exactly as on the
// file it came from.
#include "framework/Executor.h"
#include "io/CaptureSource.h"

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace fp::io {

class MemoryCapture {
public:
    /// `name` stands for the capture in errors and reports.
    MemoryCapture(std::string name, int64_t frame) : mName(std::move(name)), mFrame(frame) {}

    /// Adds `buffer`: a semantic buffer with its channel count, or a Truth.* layer of 1, 3 or 4
    /// channels, as large as the buffers added before it. Throws fp::UsageError naming the buffer
    /// otherwise. The pixels go through the input policy (sanitizeBuffer) unless `sanitized`
    /// says they already have (buffers read through a CaptureSource).
    void add(const std::string& buffer, Image image, bool sanitized = false);
    /// The channel names buffer `buffer` has when it is `channels` wide: a semantic buffer's own
    /// (and only at its width), or a Truth.* layer's of 1, 3 or 4. Throws fp::UsageError naming
    /// the buffer for any other name or width.
    static std::vector<std::string> channelNames(const std::string& buffer, int channels);
    /// The frame's camera; the passes that reproject or trace rays need one.
    void setCamera(const FrameCamera& camera) { mCamera = camera; }
    /// What was assumed or changed on the way in, each said once.
    void note(const std::string& text);

    const std::string& name() const { return mName; }
    int64_t frame() const { return mFrame; }
    Extent extent() const { return mExtent; }
    const std::map<std::string, Image>& buffers() const { return mBuffers; }
    const std::optional<FrameCamera>& camera() const { return mCamera; }
    const std::vector<std::string>& notes() const { return mNotes; }
    const SanitizeCounts& sanitized() const { return mSanitized; }
    /// The buffers a plan may read, Truth.* layers included, and the width of each Truth layer.
    std::set<std::string> availableBuffers() const;
    std::map<std::string, int> truthChannels() const;

private:
    std::string mName;
    int64_t mFrame;
    Extent mExtent;
    std::map<std::string, Image> mBuffers;
    std::optional<FrameCamera> mCamera;
    std::vector<std::string> mNotes;
    SanitizeCounts mSanitized;
};

/// Every buffer a capture file gives through its profile, decoded and sanitised as a run reads
/// it, with its camera (header or sidecar) and what reading it assumed.
MemoryCapture readCapture(const std::string& path, const CaptureProfile& profile);

/// A MemoryCapture as the executor reads a frame: its buffers shared, not copied. The scene, its
/// lights and the OCIO config come from `options` as for a CaptureSource (only the frame's
/// first-in-sequence flag of the rest counts).
class MemoryCaptureSource final : public SceneBackedSource {
public:
    MemoryCaptureSource(std::shared_ptr<const MemoryCapture> capture, CaptureOptions options);
    FrameInfo frameInfo() override;
    Texture loadBuffer(const std::string& buffer, int channels) override;

private:
    std::shared_ptr<const MemoryCapture> mCapture;
};

}  // namespace fp::io
