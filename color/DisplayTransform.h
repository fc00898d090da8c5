#pragma once
// An OpenColorIO display/view transform applied to a whole image: any 1–4 channel buffer becomes
// display-referred RGB in [0, 1]. Colour buffers go through the transform; data buffers are only
// exposed and clamped, so a preview of depth or an error image shows the numbers themselves.
// Used by the display pass and by the commands that write previews (compare, bench).
#include "foundation/Image.h"

#include <OpenColorIO/OpenColorIO.h>

#include <optional>
#include <string>

namespace fp {

class DisplayTransform {
public:
    /// `display`/`view` empty = the config's defaults; `colorManaged` false = data buffer.
    DisplayTransform(const OCIO_NAMESPACE::ConstConfigRcPtr& config, const std::string& inputSpace,
                     const std::string& display, const std::string& view, float exposureStops,
                     bool colorManaged);

    /// Writes the preview of `src` into `dst` (same size, 3 channels).
    void apply(const Image& src, Image& dst) const;
    Image apply(const Image& src) const;
    /// The transform baked for the GPU (DisplayKernel.h): 3 planes of kHalfLutSize × 1, entry i
    /// the processor's output at the half with bits i (non-finite halves hold ±65504's value).
    /// Empty for a data buffer or a transform with channel crosstalk.
    std::optional<Image> halfLut() const;

private:
    OCIO_NAMESPACE::ConstCPUProcessorRcPtr mCpu;  // null for data buffers
    float mGain;
};

}  // namespace fp
