#pragma once
// A display preview of any buffer through an OpenColorIO display/view transform. Colour buffers
// are converted from the working space; data buffers (depth, normals, HZB) are never
// colour-converted, only exposed, so the numbers in the preview are the numbers in the buffer.
#include "passes/core/Params.h"
#include "passes/core/Pass.h"

namespace fp {

struct DisplayParams {
    std::string inputSpace = "scene_linear";    //!< OCIO colour space or role of the input
    std::string display;                        //!< "" = the config's default display
    std::string view;                           //!< "" = the display's default view
    float exposure = 0.0f;                      //!< stops applied before the transform, [-20, 20]
};

class DisplayTransform;

inline constexpr const char* kDisplayColor = "color";
inline constexpr const char* kDisplayImage = "image";

class DisplayPass final : public Pass {
public:
    using Params = DisplayParams;
    static ParamSpec<Params> paramSpec();
    explicit DisplayPass(const Params& params) : mParams(params) {}

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    void checkColorConfig(const OCIO_NAMESPACE::ConstConfigRcPtr& config) const override;

#if FP_HAVE_CUDA
    bool hasCudaKernel() const override { return true; }
    void executeCuda(PassContext& ctx) override;  // DisplayPass.cu
#endif

private:
    /// The OCIO transform of this pass's parameters (exposure only for a data input).
    DisplayTransform transform(PassContext& ctx) const;

    Params mParams;
    // The baked transform on the GPU, made on the first frame (DisplayKernel.h); empty when the
    // input is data or the transform mixes channels.
    bool mLutBaked = false;
    DeviceTexture mDeviceLut;
};

}  // namespace fp
