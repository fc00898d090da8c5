// DisplayPass on the GPU: the same exposure, channel mapping and clamp as the CPU; the OCIO
// transform through its half-float table (DisplayKernel.h), baked and uploaded on the first frame,
// or Unreal's film curve computed per pixel by the same code as on the CPU.
#include "foundation/Cuda.h"
#include "foundation/CudaLaunch.cuh"
#include "passes/display/DisplayKernel.h"
#include "passes/display/DisplayPass.h"
#include "color/DisplayTransform.h"

namespace fp {

void DisplayPass::executeCuda(PassContext& ctx) {
    const bool colorManaged = ctx.inputKind(kDisplayColor) == PortKind::Color;
    const std::optional<color::FilmParams> curve = colorManaged ? film() : std::nullopt;
    if (colorManaged && !curve && !mLutBaked) {
        if (std::optional<Image> lut = transform(ctx).halfLut())
            mDeviceLut = cuda::upload(Texture(std::move(*lut)));
        mLutBaked = true;
    }
    if (colorManaged && !curve && mDeviceLut.empty()) {
        execute(ctx);  // a view that mixes channels: OCIO on the CPU (the input is copied down)
        return;
    }
    const DeviceImage& src = ctx.deviceInput(kDisplayColor)->image();
    const int w = src.width(), h = src.height();
    DeviceImage& out = ctx.deviceOutput(kDisplayImage, {{w, h}}, false).image();  // every pixel written
    display::Frame f{};
    f.channels = std::min(src.channelCount(), 4);
    for (int c = 0; c < f.channels; ++c)
        f.src[c] = viewOf(src.plane(c));
    f.gain = std::exp2(mParams.exposure);
    f.film = curve.has_value();
    if (curve) f.filmParams = *curve;
    for (int c = 0; c < 3; ++c) {
        if (colorManaged && !curve)
            f.lut[c] = viewOf(mDeviceLut.image().plane(c));
        f.dst[c] = out.plane(c);
    }
    CudaPixels{}.forEach<0>(
        w, h, [=] FP_HD(int x, int y, WorkCounts<0>&) { display::displayPixel(f, x, y); },
        "display");
    ctx.addWork("pixels", uint64_t(w) * h);
}

}  // namespace fp
