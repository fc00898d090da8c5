#pragma once
// A PassContext's ports seen from one backend, so a pass binds its inputs and outputs in one
// template for both: HostPorts hands out Textures (execute), DevicePorts DeviceTextures
// (executeCuda). Absent optional inputs are nullptr either way.
#include "passes/core/Cuda.h"
#include "passes/core/Pass.h"

#include <string>
#include <string_view>
#include <vector>

namespace fp {

struct HostPorts {
    PassContext& ctx;
    const Texture* input(std::string_view port) const { return ctx.input(port); }
    Texture& output(std::string_view port, const std::vector<Extent>& mips) const {
        return ctx.output(port, mips);
    }
    Texture* outputIfRequested(std::string_view port, const std::vector<Extent>& mips) const {
        return ctx.isRequested(port) ? &ctx.output(port, mips) : nullptr;
    }
    /// Zero-filled working images of the pass's own, freed with it.
    Texture scratch(const std::vector<Extent>& mips, const std::vector<std::string>& channels) const {
        std::vector<Image> levels;
        for (const Extent& e : mips)
            levels.emplace_back(e.width, e.height, channels);
        return Texture(std::move(levels));
    }
};

struct DevicePorts {
    PassContext& ctx;
    const DeviceTexture* input(std::string_view port) const { return ctx.deviceInput(port); }
    DeviceTexture& output(std::string_view port, const std::vector<Extent>& mips) const {
        return ctx.deviceOutput(port, mips);
    }
    DeviceTexture* outputIfRequested(std::string_view port, const std::vector<Extent>& mips) const {
        return ctx.isRequested(port) ? &ctx.deviceOutput(port, mips) : nullptr;
    }
    DeviceTexture scratch(const std::vector<Extent>& mips,
                          const std::vector<std::string>& channels) const {
        return cuda::allocate(mips, channels);
    }
};

}  // namespace fp
