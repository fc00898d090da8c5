#include "passes/error_measure/ErrorMeasurePass.h"

#include "screenspace/GBuffer.h"
#include "foundation/Error.h"
#include "metrics/ErrorMetrics.h"
#include "metrics/Heatmap.h"
#include "foundation/Tiles.h"

#include <limits>
#include <optional>

namespace fp {

ParamSpec<ErrorMeasureParams> ErrorMeasurePass::paramSpec() {
    ParamSpec<ErrorMeasureParams> s;
    s.add("tolerance", &Params::tolerance, "relative tolerance for the over-tolerance fraction")
        .range(0, 1e6);
    s.add("skyDistance", &Params::skyDistance, "depths at or beyond this are sky; 0 = only +inf")
        .range(0, 1e30);
    s.add("heatScale", &Params::heatScale,
          "|error| at the top of the heat map; 0 = 99th percentile")
        .range(0, 1e30);
    s.add("maxRoughness", &Params::maxRoughness,
          "> 0: measure only pixels whose roughness (input `roughness`) is at most this, e.g. "
          "SSR's cutoff; 0 = every pixel")
        .range(0, 1);
    s.add("excludeAbove", &Params::excludeAbove,
          "with input `exclude` bound: pixels where it is above this are left out (0: every "
          "non-zero pixel, e.g. each pixel that reflects an emitter with "
          "capture:Truth.ReflectedEmitter)")
        .range(0, 1e30);
    s.add("flip", &Params::flip,
          "FLIP, NVIDIA's perceptual error, beside the figures (metric flip, output flip): hdr "
          "for linear values (HDR-FLIP, exposures from the reference), ldr for display-referred "
          "ones in [0, 1]; off. Taken on the CPU")
        .choices({"off", "hdr", "ldr"});
    s.add("flipPixelsPerDegree", &Params::flipPixelsPerDegree,
          "FLIP's observer: pixels per degree of visual angle (67.02: a 0.7 m wide 3840-pixel "
          "monitor seen from 0.7 m)")
        .range(1, 1000);
    return s;
}

PassIO ErrorMeasurePass::describe() const {
    PassIO io;
    io.roles.measuresError = true;  // bench's error of a setting
    io.inputs = {
        {.name = kSource, .channels = {}, .doc = "the result to measure (any pass output)"},
        {.name = kReference, .channels = {}, .doc = "the reference, e.g. capture:Truth.AO"},
        {.name = kReferenceStdErr,
         .channels = {},
         .optional = true,
         .doc = "the reference's standard error (capture:Truth.<Name>.StdErr): reports its noise "
                "floor"},
        gbuffer::depthInput("sky pixels are left out", true),
    };
    io.inputs.push_back({.name = kExclude,
                         .channels = {},
                         .optional = true,
                         .doc = "pixels where its first channel is above excludeAbove are left out, "
                                "e.g. capture:Truth.ReflectedEmitter (where a reflection shows a "
                                "light's visible shape)"});
    if (mParams.maxRoughness > 0.0f)
        io.inputs.push_back(gbuffer::roughnessInput("pixels rougher than maxRoughness are left out"));
    io.outputs = {
        {.name = kHeat,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "|error| as a viridis heat map"},
        {.name = kAbsError, .channels = {"Y"}, .doc = "per-pixel mean |error| over the channels"},
    };
    if (mParams.flip != "off")
        io.outputs.push_back({.name = kFlip, .channels = {"Y"}, .doc = "FLIP's per-pixel error, 0 to 1"});
    return io;
}

void ErrorMeasurePass::reportStats(PassContext& ctx, const ErrorStats& s) const {
    for (const auto& [name, value] : s.figures())
        ctx.addMetric(name, value);
    ctx.addWork("pixels", s.pixels);
    ctx.addWork("skippedPixels", s.maskedPixels);
}

PassMemory ErrorMeasurePass::memoryBytes(Extent frame) const {
    // The mask and |error| planes, and the heat map's sorted copy of |error| (its percentile).
    const std::size_t pixels = std::size_t(frame.width) * std::size_t(frame.height);
    return {2 * imageBytes(frame, 1) + 3 * sizeof(float) * pixels, 0};
}

void ErrorMeasurePass::execute(PassContext& ctx) {
    const Image& b = ctx.input(kReference)->image();
    const Image& a = ctx.input(kSource)->image();
    const Texture* sigma = ctx.input(kReferenceStdErr);
    const Texture* depth = ctx.input(gbuffer::kDepth);
    const Texture* roughness = mParams.maxRoughness > 0.0f ? ctx.input(kRoughness) : nullptr;
    const Texture* exclude = ctx.input(kExclude);
    for (const auto& [port, t] : {std::pair{kRoughness, roughness}, std::pair{kExclude, exclude}})
        FP_CHECK(!t || (t->image().width() == b.width() && t->image().height() == b.height()),
                 "error_measure: input '{}' is {}×{}, the reference {}×{}", port,
                 t->image().width(), t->image().height(), b.width(), b.height());
    ErrorMask select = maskThresholds();
    if (depth) select.depth = viewOf(depth->image().plane(0));
    if (roughness) select.roughness = viewOf(roughness->image().plane(0));
    if (exclude) select.exclude = viewOf(exclude->image().plane(0));
    std::optional<Image> mask;
    if (select.any()) {
        mask = Image(b.width(), b.height(), {"Y"});
        forEachTile(b.width(), b.height(), [&](const Tile& t) {
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) mask->plane(0).at(x, y) = select.at(x, y);
        });
    }
    Image absError(b.width(), b.height(), {"Y"});
    ErrorInputs in;
    in.result = &a;
    in.reference = &b;
    in.referenceStdErr = sigma ? &sigma->image() : nullptr;
    in.mask = mask ? &*mask : nullptr;
    in.tolerance = mParams.tolerance;
    in.halfSource = isHalfResolution({a.width(), a.height()}, {b.width(), b.height()});
    const ErrorStats s = measureError(in, &absError);
    reportStats(ctx, s);

    if (ctx.isRequested(kHeat)) {
        const float scale =
            mParams.heatScale > 0.0f ? mParams.heatScale : heatScale(absError, in.mask);
        ctx.output(kHeat, {{b.width(), b.height()}}).image() = heatmap(absError, in.mask, scale);
        ctx.addMetric("heatScale", scale);
    }
    if (ctx.isRequested(kAbsError))
        ctx.output(kAbsError, {{b.width(), b.height()}}).image() = std::move(absError);
    if (mParams.flip != "off") {
        FP_CHECK(!in.halfSource, "error_measure: FLIP compares images of one size; the source is "
                                 "at half the reference's resolution");
        FlipOptions o;
        o.hdr = mParams.flip == "hdr";
        o.pixelsPerDegree = mParams.flipPixelsPerDegree;
        Image map;
        const FlipResult f = fp::flip(b, a, in.mask, o, ctx.isRequested(kFlip) ? &map : nullptr);
        ctx.addMetric("flip", f.mean);
        if (ctx.isRequested(kFlip)) ctx.output(kFlip, {{b.width(), b.height()}}).image() = std::move(map);
    }
}

}  // namespace fp
