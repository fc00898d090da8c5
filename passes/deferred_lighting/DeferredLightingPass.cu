// DeferredLightingPass on the GPU: the scalar reference (deferred_lighting::shadePixel) for every
// pixel, one thread each; the rect light's grid and the skin table copied for the frame.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/deferred_lighting/DeferredLightingKernel.h"
#include "passes/deferred_lighting/DeferredLightingPass.h"

namespace fp {

void DeferredLightingPass::executeCuda(PassContext& ctx) {
    const FrameInfo& frame = ctx.frame();
    const DevicePorts ports{ctx};
    std::vector<Vec3f> rectPoints;
    const deferred_lighting::LightShape light = lightShape(ctx, rectPoints);
    const auto points = ports.constants(rectPoints.data(), rectPoints.size());
    const PreintegratedSkinLut& skin = PreintegratedSkinLut::instance();
    const auto skinTexels = ports.constants(skin.texels().data(), skin.texels().size());
    const deferred_lighting::Frame f =
        deferred_lighting::bindFrame(ports, frame, light, points.get(), {skinTexels.get()});
    using deferred_lighting::kCounterCount;
    const auto counts = CudaPixels{}.forEach<kCounterCount>(
        frame.extent.width, frame.extent.height,
        [=] FP_HD(int x, int y, WorkCounts<kCounterCount>& n) {
            deferred_lighting::shadePixel(f, x, y, deferred_lighting::startPixel(f, x, y), n.value);
        },
        "deferred_lighting");
    ctx.addWork("pixels", counts[deferred_lighting::kLit]);
    ctx.addWork("skippedPixels", counts[deferred_lighting::kSkipped]);
}

}  // namespace fp
