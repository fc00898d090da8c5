#include "passes/display/DisplayPass.h"

#include "color/DisplayTransform.h"

namespace fp {


ParamSpec<DisplayParams> DisplayPass::paramSpec() {
    ParamSpec<DisplayParams> s;
    s.add("inputSpace", &Params::inputSpace, "OCIO colour space (or role) of colour inputs");
    s.add("display", &Params::display, "OCIO display; empty = the config's default");
    s.add("view", &Params::view, "OCIO view; empty = the display's default");
    s.add("exposure", &Params::exposure, "exposure in stops before the transform").range(-20, 20);
    s.add("tonemapper", &Params::tonemapper,
          "ocio: the OCIO display and view; ue4.27-film: Unreal 4.27's filmic tonemapper and the "
          "sRGB encoding (the input read as scene-linear Rec.709; docs/color.md)")
        .choices({"ocio", "ue4.27-film"});
    // Unreal's post-process Film* settings and their defaults (a post-process volume's, not cvars).
    s.add("filmSlope", &Params::filmSlope, "the film curve's slope in log10 (Unreal's FilmSlope)")
        .range(0.01, 1);
    s.add("filmToe", &Params::filmToe, "the toe's size: how soon the darks bend (FilmToe)")
        .range(0, 1);
    s.add("filmShoulder", &Params::filmShoulder,
          "the shoulder's size: how soon the highlights bend (FilmShoulder)")
        .range(0, 1);
    s.add("filmBlackClip", &Params::filmBlackClip, "where the toe reaches black (FilmBlackClip)")
        .range(0, 1);
    s.add("filmWhiteClip", &Params::filmWhiteClip,
          "where the shoulder reaches white (FilmWhiteClip)")
        .range(0, 1);
    return s;
}

std::optional<color::FilmParams> DisplayPass::film() const {
    if (mParams.tonemapper != "ue4.27-film") return std::nullopt;
    return color::FilmParams{mParams.filmSlope, mParams.filmToe, mParams.filmShoulder,
                             mParams.filmBlackClip, mParams.filmWhiteClip};
}

PassIO DisplayPass::describe() const {
    PassIO io;
    // No channel list: any 1–4 channel buffer can be previewed (1 channel shows as grey).
    io.inputs = {{.name = kDisplayColor,
                  .channels = {},
                  .kind = PortKind::Color,
                  .captureDefault = "SceneColor",
                  .doc = "buffer to preview"}};
    io.outputs = {{.name = kDisplayImage,
                   .channels = {"R", "G", "B"},
                   .kind = PortKind::Color,
                   .doc = "display-referred RGB in [0, 1] (write it to a .png)",
                   .displayReferred = true}};
    io.needsColorConfig = true;
    return io;
}

DisplayTransform DisplayPass::transform(PassContext& ctx) const {
    const bool colorManaged = ctx.inputKind(kDisplayColor) == PortKind::Color;
    return DisplayTransform(colorManaged ? ctx.colorConfig() : nullptr, mParams.inputSpace,
                            mParams.display, mParams.view, mParams.exposure, colorManaged,
                            film());
}

void DisplayPass::checkColorConfig(const OCIO_NAMESPACE::ConstConfigRcPtr& config) const {
    DisplayTransform(config, mParams.inputSpace, mParams.display, mParams.view, mParams.exposure,
                     true);
}

void DisplayPass::execute(PassContext& ctx) {
    const Image& src = ctx.input(kDisplayColor)->image();
    Texture& out = ctx.output(kDisplayImage, {{src.width(), src.height()}});
    transform(ctx).apply(src, out.image());
    ctx.addWork("pixels", uint64_t(src.width()) * src.height());
}

}  // namespace fp
