#include "screenspace/SignalDenoiser.h"

#include "screenspace/GBuffer.h"
#include "screenspace/Surface.h"
#include "screenspace/TraceResolution.h"

namespace fp::ssd {

int upscaleOf(Extent frame, Extent signal) {
    for (int k = 1; k <= 4; ++k)
        if (traceExtent(frame, k) == signal)
            return k;
    return 0;
}

const std::vector<std::string>& stateChannels() {
    static const std::vector<std::string> names = {"R", "G", "B", "A", "N", "D", "NX", "NY", "NZ"};
    return names;
}

std::vector<PortSpec> denoiserInputs(Footprint footprint) {
    std::vector<PortSpec> in = {
        {.name = kHitDistance,
         .channels = {"Y"},
         .doc = "the rays' hit distance, scene units, as the tracing pass wrote it (sizes the "
                "kernels; −1 no hit, −2 no ray: passed through)"},
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit and sky pixels pass through"),
        gbuffer::velocityInput(
            "optional motion for reprojection; the history's camera is used when unbound"),
    };
    if (footprint == Footprint::Specular)
        in.push_back(gbuffer::roughnessInput("sizes the kernel with the lobe (α = roughness²)"));
    return in;
}

PassMemory memoryOf(Extent frame, int channels, bool enabled, bool temporalAccumulation) {
    if (!enabled) return {};
    const std::size_t state = temporalAccumulation ? imageBytes(frame, int(stateChannels().size())) : 0;
    const std::size_t grid = sizeof(Surface) * std::size_t(frame.width) * std::size_t(frame.height);
    return {grid + imageBytes(frame, 1) + 2 * imageBytes(frame, channels) + state, state};
}

}  // namespace fp::ssd
