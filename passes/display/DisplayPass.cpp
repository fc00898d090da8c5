#include "passes/display/DisplayPass.h"

#include "passes/core/Error.h"
#include "passes/core/Tiles.h"

#include <algorithm>
#include <cmath>

namespace fp {

namespace OCIO = OCIO_NAMESPACE;

namespace {
constexpr const char* kColor = "color";
constexpr const char* kImage = "image";
}  // namespace

ParamSpec<DisplayParams> DisplayPass::paramSpec() {
    ParamSpec<DisplayParams> s;
    s.add("inputSpace", &Params::inputSpace, "OCIO colour space (or role) of colour inputs");
    s.add("display", &Params::display, "OCIO display; empty = the config's default");
    s.add("view", &Params::view, "OCIO view; empty = the display's default");
    s.add("exposure", &Params::exposure, "exposure in stops before the transform").range(-20, 20);
    return s;
}

PassIO DisplayPass::describe() const {
    PassIO io;
    // No channel list: any 1–4 channel buffer can be previewed (1 channel shows as grey).
    io.inputs = {{kColor, {}, PortKind::Color, false, "capture:SceneColor", "buffer to preview"}};
    io.outputs = {{kImage, {"R", "G", "B"}, PortKind::Color, false, "",
                   "display-referred RGB in [0, 1] (write it to a .png)"}};
    io.needsColorConfig = true;
    return io;
}

void DisplayPass::execute(PassContext& ctx) {
    const Texture& in = *ctx.input(kColor);
    const Image& src = in.image();
    const bool isData = ctx.inputKind(kColor) == PortKind::Data;
    Texture& out = ctx.output(kImage, {{src.width(), src.height()}});
    Image& dst = out.image();
    const float gain = std::exp2(mParams.exposure);

    OCIO::ConstCPUProcessorRcPtr cpu;
    if (!isData) {
        OCIO::ConstConfigRcPtr config = ctx.colorConfig();
        try {
            const std::string display =
                mParams.display.empty() ? config->getDefaultDisplay() : mParams.display;
            const std::string view =
                mParams.view.empty() ? config->getDefaultView(display.c_str()) : mParams.view;
            auto transform = OCIO::DisplayViewTransform::Create();
            transform->setSrc(mParams.inputSpace.c_str());
            transform->setDisplay(display.c_str());
            transform->setView(view.c_str());
            cpu = config->getProcessor(transform)->getDefaultCPUProcessor();
        } catch (const OCIO::Exception& e) {
            throw Error(fmt::format("OCIO display transform (space '{}', display '{}', view "
                                    "'{}'): {}",
                                    mParams.inputSpace, mParams.display, mParams.view, e.what()));
        }
    }
    const int channels = src.channelCount();
    forEachTile(src.width(), src.height(), [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int c = 0; c < 3; ++c) {
                // 1 channel → grey; 2 channels → R, G and a black B.
                const int from = channels == 1 ? 0 : c;
                float* d = dst.plane(c).row(y);
                if (from >= channels) {
                    std::fill(d + t.x0, d + t.x1, 0.0f);
                    continue;
                }
                const float* s = src.plane(from).row(y);
                for (int x = t.x0; x < t.x1; ++x) {
                    const float v = s[x] * gain;
                    d[x] = std::isfinite(v) ? v : 0.0f;  // no NaN/Inf reaches a preview
                }
            }
        if (cpu) {
            const long w = t.x1 - t.x0, h = t.y1 - t.y0;
            const std::ptrdiff_t yStride = dst.plane(0).stride() * std::ptrdiff_t(sizeof(float));
            OCIO::PlanarImageDesc desc(dst.plane(0).row(t.y0) + t.x0, dst.plane(1).row(t.y0) + t.x0,
                                       dst.plane(2).row(t.y0) + t.x0, nullptr, w, h,
                                       OCIO::BIT_DEPTH_F32, sizeof(float), yStride);
            cpu->apply(desc);
        }
        for (int c = 0; c < 3; ++c)
            for (int y = t.y0; y < t.y1; ++y) {
                float* d = dst.plane(c).row(y);
                for (int x = t.x0; x < t.x1; ++x) d[x] = std::clamp(d[x], 0.0f, 1.0f);
            }
        ctx.addWork("pixels", uint64_t(t.x1 - t.x0) * (t.y1 - t.y0));
    });
}

}  // namespace fp
