#pragma once
// The resolution a screen-space trace runs at, which its denoiser runs at too: the frame, or
// with half resolution (r.SSGI.HalfRes) half of it rounded up (algorithms §4.3). Here rather
// than in the trace's pass, so that the denoiser does not include another pass.
#include "foundation/Image.h"

namespace fp {

inline Extent traceExtent(Extent frame, bool halfRes) {
    return halfRes ? Extent{(frame.width + 1) / 2, (frame.height + 1) / 2} : frame;
}

}  // namespace fp
