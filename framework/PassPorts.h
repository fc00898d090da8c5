#pragma once
// A PassContext's ports seen from one backend, so a pass binds its inputs and outputs in one
// template for both: HostPorts hands out Textures (execute), DevicePorts DeviceTextures
// (executeCuda). Absent optional inputs are nullptr either way.
#include "foundation/Bvh.h"
#include "foundation/Cuda.h"
#include "foundation/RayScene.h"
#include "framework/Pass.h"

#include <cstddef>
#include <memory>
#include <type_traits>
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
    /// An output the pass writes at every pixel of every level: allocated without clearing.
    Texture& overwrite(std::string_view port, const std::vector<Extent>& mips) const {
        return ctx.output(port, mips, false);
    }
    Texture* overwriteIfRequested(std::string_view port, const std::vector<Extent>& mips) const {
        return ctx.isRequested(port) ? &overwrite(port, mips) : nullptr;
    }
    /// Zero-filled working images of the pass's own, freed with it.
    Texture scratch(const std::vector<Extent>& mips, const std::vector<std::string>& channels) const {
        std::vector<Image> levels;
        for (const Extent& e : mips)
            levels.emplace_back(e.width, e.height, channels);
        return Texture(std::move(levels));
    }
    /// Last frame's state of a temporal pass; nullptr without a usable history.
    const Texture* historyState() const {
        return ctx.history() ? &ctx.history()->state : nullptr;
    }
    void keepHistory(Texture state) const { ctx.keepHistory(std::move(state)); }
    /// Uninitialised scratch memory for `count` values of a plain type, freed with the pass
    /// (foundation's hostScratch: recycled from frame to frame). Nothing is constructed — the
    /// pass writes every value before it reads one, as on the GPU — so no thread walks the array
    /// first: a 1080p denoiser's 2 M surfaces were constructed one by one, and the pages faulted
    /// in, on one thread before its parallel loops.
    template <class T>
    std::shared_ptr<T> scratchArray(std::size_t count) const {
        static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T> &&
                      alignof(T) <= 64);
        return std::static_pointer_cast<T>(hostScratch(count * sizeof(T)));
    }
    /// `count` values of a plain type where the pixels read them: here, the values themselves
    /// (not copied, not owned: they must outlive the pass's pixels).
    template <class T>
    std::shared_ptr<const T> constants(const T* data, std::size_t) const {
        return std::shared_ptr<const T>(std::shared_ptr<const T>{}, data);
    }
    /// The scene's BVH (Bvh.h) in host memory.
    BvhView bvh() const { return ctx.scene().bvh(); }
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
    /// An output the pass writes at every pixel of every level: not cleared first.
    DeviceTexture& overwrite(std::string_view port, const std::vector<Extent>& mips) const {
        return ctx.deviceOutput(port, mips, false);
    }
    DeviceTexture* overwriteIfRequested(std::string_view port,
                                        const std::vector<Extent>& mips) const {
        return ctx.isRequested(port) ? &ctx.deviceOutput(port, mips, false) : nullptr;
    }
    DeviceTexture scratch(const std::vector<Extent>& mips,
                          const std::vector<std::string>& channels) const {
        return cuda::allocate(mips, channels);
    }
    const DeviceTexture* historyState() const {
        return ctx.history() ? &ctx.history()->deviceState : nullptr;
    }
    void keepHistory(DeviceTexture state) const { ctx.keepHistory(std::move(state)); }
    template <class T>
    std::shared_ptr<T> scratchArray(std::size_t count) const {
        return std::static_pointer_cast<T>(cuda::allocateBytes(count * sizeof(T)));
    }
    /// A device copy of `count` values of a plain type.
    template <class T>
    std::shared_ptr<const T> constants(const T* data, std::size_t count) const {
        return std::static_pointer_cast<const T>(cuda::uploadBytes(data, count * sizeof(T)));
    }
    /// The scene's BVH in GPU memory, uploaded once per scene.
    BvhView bvh() const { return ctx.scene().deviceBvh(); }
};

}  // namespace fp
