#pragma once
// The pass contract.
//
// Common principles, for every pass:
// - Declare, then execute (Falcor reflect/execute, Filament setup/execute). `describe()` names the
//   input and output ports, their channels and whether the pass needs the camera, the scene's
//   geometry or the colour configuration. It may depend on the parameters and is called once per
//   plan, before any pixel is read.
// - Ports are addressed as "pass.port" in the config; capture buffers as "capture:SceneDepth". An
//   input may name the capture buffer it reads when the config says nothing (`captureDefault`);
//   it never names another pass: which pass feeds which is written only in the chain (presets and
//   configs), so the chain can be read in one place.
// - Optional inputs that nobody bound come back as nullptr; outputs nobody asked for report
//   `isRequested() == false`, and a pass skips the work behind them.
// - A pass only computes: it never includes io/, never opens files, never creates threads. It
//   fans out through forEachTile (Tiles.h) on the shared oneTBB pool.
// - Random numbers come from Rng(frame, x, y, seed) (Random.h), so output is bit-identical for
//   any thread count and any frame chunking.
// - Bad input is an fp::Error with context; a bug is an FP_ASSERT.
// - Work counts ("pixels", "skippedPixels", "rays", ...) go through addWork so the run report can
//   show throughput next to wall time.
// - A pass with a CUDA kernel (docs/gpu.md) keeps its per-pixel maths in an FP_HD function that
//   execute() and the kernel in its .cu file both call; on the GPU it reads deviceInput() and writes
//   deviceOutput(), and the executor moves images between host and device only where they cross.
#include "foundation/Camera.h"
#include "foundation/DeviceImage.h"
#include "foundation/Image.h"

#include <OpenColorIO/OpenColorIO.h>

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace fp {

class RayScene;
struct Light;
struct Environment;

/// Where a step of the plan runs.
enum class Device { Cpu, Cuda };

/// Colour buffers may be colour-managed and stored as half; data buffers never are.
enum class PortKind { Color, Data };

/// One input or output port. Written with designated initialisers:
/// `{.name = kDepth, .channels = {"Z"}, .captureDefault = "SceneDepth", .doc = "…"}`. The members
/// a declaration may leave out have default initialisers (`{}`): GCC's -Wmissing-field-initializers
/// warns of any left out that has none.
struct PortSpec {
    std::string name;
    std::vector<std::string> channels;  //!< channel suffixes, e.g. {"R","G","B"} or {"Z"}
    PortKind kind = PortKind::Data;
    bool optional = false;       //!< an unbound optional input reaches the pass as nullptr
    std::string captureDefault{};  //!< inputs: the capture buffer read when the config binds none
    std::string doc{};
    /// Optional inputs the config leaves unbound: the capture buffer bound instead on a frame
    /// whose camera has no previous camera (the first frame of a Blender sequence), so motion
    /// comes from the capture's own velocity rather than from a camera it does not have.
    std::string captureWhenNoPreviousCamera{};
    /// Outputs: colour already display-encoded (a display transform's result): a viewer draws
    /// it as it is, never through a view again.
    bool displayReferred = false;
};

/// What the application's error tools (bench's error breakdown and its bare ray loop) need to
/// know of a pass. The pass declares it, so the application never names a pass type.
struct PassRoles {
    /// Measures input "source" against input "reference" and reports its figures (rmse, ...)
    /// through addMetric: a bench setting's error. An optional "depth" input with the
    /// "skyDistance" parameter leaves the sky out.
    bool measuresError = false;
    /// A tracer whose noise this integer parameter sets (its rays per pixel): the breakdown's
    /// converged rung runs the chain with it raised.
    std::string raysParam;
    /// A screen-space oracle (the best any screen-space method does with the frame's depth and
    /// colour): per capture truth layer, the output that estimates the same quantity. Its ray
    /// count is raysParam.
    std::map<std::string, std::string> oracleFor;
    /// A ray-traced GI pass: its paths' bounce count. With raysParam, the breakdown's ladder for
    /// it has no screen-space rungs: converged (raysParam raised), every bounce (this raised),
    /// the truth — what is left is light the pass leaves out.
    std::string bouncesParam;
    /// Traces rays through RayScene: bench replays them in bare Embree loops.
    bool tracesRays = false;
    /// A method Unreal turns on with one setting ("r.RayTracing.GlobalIllumination=1"): tune
    /// names it when its search chose among methods. Empty for the rest.
    std::string unrealSwitch;
    /// framepass's own method, which no Unreal setting gives (tune says so).
    bool framepassOwn = false;
};

struct PassIO {
    std::vector<PortSpec> inputs, outputs;
    PassRoles roles;
    bool needsCamera = false;  //!< frame().camera must be known
    bool needsScene = false;   //!< geometry is loaded and a BVH built only if a live pass says so
    bool needsLights = false;  //!< the scene's lights are read (not its geometry)
    bool needsEnvironment = false;  //!< the scene's sky light (none when the config names no scene)
    bool needsColorConfig = false;    //!< an OCIO config must be loaded
    std::string workUnit = "pixels";  //!< the counter that measures throughput
    bool temporal = false;            //!< keeps state from frame to frame (PassContext::history)
};

/// What a pass knows about the frame it runs on.
struct FrameInfo {
    int64_t number = 1;  //!< absolute frame number (seeds the RNG)
    Extent extent;       //!< full-resolution size of the capture
    FrameCamera camera;
    bool hasCamera = false;
    bool firstInSequence = true;  //!< no history from an earlier frame
};

/// What a temporal pass kept at the end of its last frame, with the camera it was made with (the
/// pass reprojects through that camera, so a history is usable whatever the frame step). The
/// state lives where the pass ran: `state` on the host, `deviceState` on the GPU; the executor
/// copies it across before the pass runs if the pass now runs on the other side.
struct PassHistory {
    Texture state;
    DeviceTexture deviceState;
    CameraView camera;
};

class PassContext {
public:
    virtual ~PassContext() = default;
    /// The texture bound to an input port; nullptr for an unbound optional input.
    virtual const Texture* input(std::string_view port) const = 0;
    virtual PortKind inputKind(std::string_view port) const = 0;
    /// False when nothing downstream reads this output: skip the work behind it.
    virtual bool isRequested(std::string_view port) const = 0;
    /// Allocates the output with the given mip extents and the port's channels, zero-filled
    /// unless the pass says it writes every pixel of every level (`zeroed` false: a 1080p plane is
    /// 8 MB, and clearing rt_reflections' five planes was a third of a frame whose texels all
    /// skip, 1 of 3.4 ms on two cores).
    virtual Texture& output(std::string_view port, const std::vector<Extent>& mips,
                            bool zeroed = true) = 0;
    virtual const FrameInfo& frame() const = 0;
    /// The ray-traceable scene, built on first use (only passes with needsScene may call it).
    virtual const RayScene& scene() = 0;
    /// The scene's lights, read without its geometry (passes with needsLights or needsScene).
    virtual const std::vector<Light>& lights() = 0;
    /// The scene's sky light; an empty one when the config names no scene (only passes with
    /// needsEnvironment may call it).
    virtual const Environment& environment() = 0;
    /// The OCIO config (only passes with needsColorConfig may call it).
    virtual OCIO_NAMESPACE::ConstConfigRcPtr colorConfig() = 0;
    /// Adds to a named work counter; thread-safe, call once per tile rather than per pixel.
    virtual void addWork(std::string_view counter, uint64_t amount) = 0;
    /// Last frame's state of this (temporal) pass; nullptr on the first frame of a sequence, after
    /// a camera cut, or when the frame size changed.
    virtual const PassHistory* history() const = 0;
    /// Keeps `state` (made with this frame's camera) for the next frame.
    virtual void keepHistory(Texture state) = 0;
    /// The same for a pass on the GPU: the state stays in device memory between frames.
    virtual void keepHistory(DeviceTexture state) = 0;
    /// Reports a measured figure (error_measure's RMSE, ...) for the run report.
    virtual void addMetric(std::string_view name, double value) = 0;

    // The GPU side, for executeCuda: the same ports, resident in device memory.
    /// The device copy of an input (uploaded on first use); nullptr for an unbound optional input.
    virtual const DeviceTexture* deviceInput(std::string_view port) = 0;
    /// Allocates the output in device memory, zero-filled unless the pass says it writes every
    /// pixel of every level (`zeroed` false: clearing 8 MB a plane at 1080p is GPU time spent
    /// on values the pass overwrites).
    virtual DeviceTexture& deviceOutput(std::string_view port, const std::vector<Extent>& mips,
                                        bool zeroed = true) = 0;
};

/// Host memory a pass holds beyond its outputs, for the planner's forecast of a run's peak.
struct PassMemory {
    std::size_t scratch = 0;  //!< at most this allocated while execute() runs, freed when it returns
    std::size_t history = 0;  //!< kept between frames (its temporal state); while the pass runs,
                              //!< last frame's and the new one (in scratch) are both alive
};

class Pass {
public:
    virtual ~Pass() = default;
    virtual PassIO describe() const = 0;
    virtual void execute(PassContext& ctx) = 0;
    /// Sizes of each mip of an output for a frame of `frame` pixels; the planner uses it for the
    /// memory estimate and the pass for allocation, so the two never disagree.
    virtual std::vector<Extent> outputExtents(std::string_view port, Extent frame) const {
        return {frame};
    }
    /// What the CPU execute() allocates besides its outputs for a frame of `frame` pixels (the
    /// GPU path allocates its scratch on the device). Declared by each pass that allocates
    /// frame-sized temporaries; tests hold the forecast it feeds within 20 % of a run's peak.
    virtual PassMemory memoryBytes(Extent /*frame*/) const { return {}; }
    /// Passes with needsColorConfig: checks what the pass will ask of the colour config (a
    /// display, a view, a colour space) when the chain is planned, so a bad name fails before
    /// the first frame instead of after the chain ran. Throws fp::Error.
    virtual void checkColorConfig(const OCIO_NAMESPACE::ConstConfigRcPtr& /*config*/) const {}
    /// True where this build compiled the pass's CUDA kernel (its .cu file, FP_HAVE_CUDA).
    virtual bool hasCudaKernel() const { return false; }
    /// Runs the pass on the GPU; called only when hasCudaKernel().
    virtual void executeCuda(PassContext& ctx);
};

/// The skeleton every pass shares, written once: its parameters `P` (with defaults; the pass's
/// `static ParamSpec<P> paramSpec()` validates them and the registry calls it) kept in mParams.
/// A pass is `class HZBPass final : public PassWithParams<HZBParams>` with
/// `using PassWithParams::PassWithParams;`.
template <class P>
class PassWithParams : public Pass {
public:
    using Params = P;
    explicit PassWithParams(const Params& params) : mParams(params) {}

protected:
    Params mParams;
};

/// In a pass's class: it has a CUDA kernel (executeCuda, defined in the .cu file beside it) where
/// this build has the CUDA backend.
#if FP_HAVE_CUDA
#define FP_PASS_HAS_CUDA_KERNEL                                \
    bool hasCudaKernel() const override { return true; }      \
    void executeCuda(PassContext& ctx) override;
#else
#define FP_PASS_HAS_CUDA_KERNEL
#endif

}  // namespace fp
