#pragma once
// An OpenColorIO display/view transform applied to a whole image: any 1–4 channel buffer becomes
// display-referred RGB in [0, 1]. Colour buffers go through the transform; data buffers are only
// exposed and clamped, so a preview of depth or an error image shows the numbers themselves.
// Used by the display pass and by the commands that write previews (compare, bench).
#include "color/FilmicTonemap.h"
#include "foundation/Image.h"

#include <OpenColorIO/OpenColorIO.h>

#include <optional>
#include <string>

namespace fp {

class DisplayTransform {
public:
    /// `display`/`view` empty = the config's defaults; `colorManaged` false = data buffer.
    /// With `film`, a colour buffer goes through Unreal 4.27's filmic tonemapper and the sRGB
    /// encoding (FilmicTonemap.h) instead of the OCIO view (the input is scene-linear Rec.709).
    DisplayTransform(const OCIO_NAMESPACE::ConstConfigRcPtr& config, const std::string& inputSpace,
                     const std::string& display, const std::string& view, float exposureStops,
                     bool colorManaged, std::optional<color::FilmParams> film = std::nullopt);

    /// Writes the preview of `src` into `dst` (same size, 3 channels).
    void apply(const Image& src, Image& dst) const;
    Image apply(const Image& src) const;
    /// The transform baked for the GPU (DisplayKernel.h): 3 planes of kHalfLutSize × 1, entry i
    /// the processor's output at the half with bits i (non-finite halves hold ±65504's value).
    /// Empty for a data buffer or a transform with channel crosstalk (the film curve's too).
    std::optional<Image> halfLut() const;
    /// Unreal's filmic tonemapper and the sRGB encoding (as the display pass applies them) baked
    /// into a size³ table over log2 of each channel from kFilmCubeLog2Min to kFilmCubeLog2Max
    /// (below: the first entry, above: the last): entry (r, g, b) at pixel (r + size·g, b),
    /// 3 planes. What the workbench page looks up between neighbours for its film view.
    static Image filmCube(const color::FilmParams& film, int size);
    static constexpr float kFilmCubeLog2Min = -14.0f, kFilmCubeLog2Max = 10.0f;
    /// The film curve's parameters when this is Unreal's tonemapper, else nullopt.
    const std::optional<color::FilmParams>& film() const { return mFilm; }

private:
    OCIO_NAMESPACE::ConstCPUProcessorRcPtr mCpu;  // null for data buffers and the film curve
    float mGain;
    std::optional<color::FilmParams> mFilm;  // set only for a colour buffer
};

}  // namespace fp
