#pragma once
// The frame sources and the sink the frame driver, bench and a session run chains with: buffers
// read from the capture once, and images kept only from the run that asks for them.
#include "framework/Executor.h"

#include <map>
#include <string>

namespace fp::app {

/// A frame source that hands everything to another: the base of a source that changes one thing.
class ForwardingSource : public FrameSource {
public:
    explicit ForwardingSource(FrameSource& inner) : mInner(inner) {}
    FrameInfo frameInfo() override { return mInner.frameInfo(); }
    Texture loadBuffer(const std::string& buffer, int channels) override {
        return mInner.loadBuffer(buffer, channels);
    }
    const RayScene& scene() override { return mInner.scene(); }
    const std::vector<Light>& lights() override { return mInner.lights(); }
    const Environment& environment() override { return mInner.environment(); }
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() override { return mInner.colorConfig(); }
    InputSeconds inputSeconds() const override { return mInner.inputSeconds(); }

protected:
    FrameSource& mInner;
};

/// A frame source that reads each buffer from the capture once and serves copies afterwards,
/// so repeated runs time the passes, not the disk.
class CachedSource final : public ForwardingSource {
public:
    using ForwardingSource::ForwardingSource;
    Texture loadBuffer(const std::string& buffer, int channels) override {
        auto it = mCache.find(buffer);
        if (it == mCache.end())
            it = mCache.emplace(buffer, mInner.loadBuffer(buffer, channels)).first;
        return it->second;
    }
    const Texture* cached(const std::string& buffer) const {
        auto it = mCache.find(buffer);
        return it == mCache.end() ? nullptr : &it->second;
    }

private:
    std::map<std::string, Texture> mCache;
};

/// Discards outputs, except on the run that keeps the images for the report.
class KeepingSink final : public FrameSink {
public:
    bool keep = false;
    /// Images a CUDA step made stay on the GPU, in deviceImages.
    bool onDevice = false;
    std::map<std::string, Image> images;
    std::map<std::string, DeviceImage> deviceImages;
    bool takesDeviceImages() const override { return onDevice; }
    void write(const OutputDesc&,
               const std::vector<OutputLayer>& layers,
               const FrameInfo&) override {
        if (!keep)
            return;
        for (const auto& l : layers) {
            if (l.device) deviceImages[l.name] = l.device->image();
            else images[l.name] = l.texture->image();
        }
    }
};

}  // namespace fp::app
