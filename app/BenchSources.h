#pragma once
// The frame source and sink bench runs its chains with: buffers read from the capture once, and
// images kept only from the run that makes the report.
#include "framework/Executor.h"

#include <map>
#include <string>

namespace fp::app {

/// A frame source that reads each buffer from the capture once and serves copies afterwards,
/// so repeated runs time the passes, not the disk.
class CachedSource final : public FrameSource {
public:
    explicit CachedSource(FrameSource& inner) : mInner(inner) {}
    FrameInfo frameInfo() override { return mInner.frameInfo(); }
    Texture loadBuffer(const std::string& buffer, int channels) override {
        auto it = mCache.find(buffer);
        if (it == mCache.end())
            it = mCache.emplace(buffer, mInner.loadBuffer(buffer, channels)).first;
        return it->second;
    }
    const RayScene& scene() override { return mInner.scene(); }
    const std::vector<Light>& lights() override { return mInner.lights(); }
    const Environment& environment() override { return mInner.environment(); }
    OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() override { return mInner.colorConfig(); }
    InputSeconds inputSeconds() const override { return mInner.inputSeconds(); }
    const Texture* cached(const std::string& buffer) const {
        auto it = mCache.find(buffer);
        return it == mCache.end() ? nullptr : &it->second;
    }

private:
    FrameSource& mInner;
    std::map<std::string, Texture> mCache;
};

/// Discards outputs, except on the run that keeps the images for the report.
class KeepingSink final : public FrameSink {
public:
    bool keep = false;
    std::map<std::string, Image> images;
    void write(const OutputDesc&,
               const std::vector<OutputLayer>& layers,
               const FrameInfo&) override {
        if (!keep)
            return;
        for (const auto& l : layers)
            images[l.name] = l.texture->image();
    }
};

}  // namespace fp::app
