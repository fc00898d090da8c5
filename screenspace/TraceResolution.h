#pragma once
// The resolution a trace runs at: the frame, or with half resolution (r.SSGI.HalfRes) half of it
// rounded up (algorithms §4.3), or for a ray-traced pass 1/k of it by its screen percentage
// (§12.2). Here rather than in the trace's pass, so that the denoiser does not include another
// pass.
#include "foundation/Image.h"

namespace fp {

inline Extent traceExtent(Extent frame, bool halfRes) {
    return halfRes ? Extent{(frame.width + 1) / 2, (frame.height + 1) / 2} : frame;
}

/// A ray-traced pass's screen percentage as Unreal's UpscaleFactor: one pixel of each k × k block
/// is traced, k = int(100 / percent) with the percentage clamped to 25–100 (algorithms §12.2).
inline int screenPercentageUpscale(float percent) {
    const float p = percent < 25.0f ? 25.0f : (percent > 100.0f ? 100.0f : percent);
    return int(100.0f / p + 1e-4f);
}

/// The frame divided by k, rounded up: what a pass tracing one pixel of each k × k block writes.
inline Extent traceExtent(Extent frame, int k) {
    return {(frame.width + k - 1) / k, (frame.height + k - 1) / k};
}

}  // namespace fp
