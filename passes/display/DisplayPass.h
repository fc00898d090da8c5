#pragma once
// A display preview of any buffer through an OpenColorIO display/view transform, or through
// Unreal 4.27's filmic tonemapper (color/FilmicTonemap.h) and the sRGB encoding, as an Unreal
// viewport shows it. Colour buffers are converted from the working space; data buffers (depth,
// normals, HZB) are never colour-converted, only exposed, so the numbers in the preview are the
// numbers in the buffer.
#include "color/FilmicTonemap.h"
#include "framework/Params.h"
#include "framework/Pass.h"

namespace fp {

struct DisplayParams {
    std::string inputSpace = "scene_linear";    //!< OCIO colour space or role of the input
    std::string display;                        //!< "" = the config's default display
    std::string view;                           //!< "" = the display's default view
    float exposure = 0.0f;                      //!< stops applied before the transform, [-20, 20]
    std::string tonemapper = "ocio";            //!< "ocio" or "ue4.27-film"
    // The film curve (ue4.27-film only), Unreal's defaults.
    float filmSlope = color::FilmParams{}.slope, filmToe = color::FilmParams{}.toe,
          filmShoulder = color::FilmParams{}.shoulder, filmBlackClip = color::FilmParams{}.blackClip,
          filmWhiteClip = color::FilmParams{}.whiteClip;
};

class DisplayTransform;

inline constexpr const char* kDisplayColor = "color";
inline constexpr const char* kDisplayImage = "image";

class DisplayPass final : public PassWithParams<DisplayParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    void checkColorConfig(const OCIO_NAMESPACE::ConstConfigRcPtr& config) const override;

    FP_PASS_HAS_CUDA_KERNEL  // DisplayPass.cu

private:
    /// The transform of this pass's parameters (exposure only for a data input).
    DisplayTransform transform(PassContext& ctx) const;
    /// The film curve's parameters with tonemapper ue4.27-film, else nullopt (the OCIO view).
    std::optional<color::FilmParams> film() const;

    // The baked transform on the GPU, made on the first frame (DisplayKernel.h); empty when the
    // input is data or the transform mixes channels. Read only by the CUDA path (DisplayPass.cu):
    // a build without CUDA never uses it.
    [[maybe_unused]] bool mLutBaked = false;
    DeviceTexture mDeviceLut;
};

}  // namespace fp
