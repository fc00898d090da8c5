#include "passes/error_measure/ErrorMeasurePass.h"

#include "passes/common/GBuffer.h"
#include "passes/core/Error.h"
#include "passes/metrics/ErrorMetrics.h"
#include "passes/metrics/Heatmap.h"

#include <limits>
#include <optional>

namespace fp {

namespace {
constexpr const char* kSource = "source";
constexpr const char* kReference = "reference";
constexpr const char* kReferenceStdErr = "referenceStdErr";
constexpr const char* kHeat = "heat";
constexpr const char* kAbsError = "absError";
}  // namespace

ParamSpec<ErrorMeasureParams> ErrorMeasurePass::paramSpec() {
    ParamSpec<ErrorMeasureParams> s;
    s.add("tolerance", &Params::tolerance, "relative tolerance for the over-tolerance fraction")
        .range(0, 1e6);
    s.add("skyDistance", &Params::skyDistance, "depths at or beyond this are sky; 0 = only +inf")
        .range(0, 1e30);
    s.add("heatScale", &Params::heatScale,
          "|error| at the top of the heat map; 0 = 99th percentile")
        .range(0, 1e30);
    return s;
}

PassIO ErrorMeasurePass::describe() const {
    PassIO io;
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
    io.outputs = {
        {.name = kHeat,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "|error| as a viridis heat map"},
        {.name = kAbsError, .channels = {"Y"}, .doc = "per-pixel mean |error| over the channels"},
    };
    return io;
}

namespace {
// A half-resolution source (a half-res SSGI trace) is measured as the 4.27 composite reads it:
// point-upsampled, full-res pixel (x, y) taking texel (x/2, y/2).
Image pointUpsample(const Image& half, int width, int height) {
    Image full(width, height, half.channels());
    for (int c = 0; c < half.channelCount(); ++c)
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                full.plane(c).at(x, y) = half.plane(c).at(x / 2, y / 2);
    return full;
}
}  // namespace

void ErrorMeasurePass::execute(PassContext& ctx) {
    const Image& b = ctx.input(kReference)->image();
    const Image& source = ctx.input(kSource)->image();
    std::optional<Image> upsampled;
    if (source.width() == (b.width() + 1) / 2 && source.height() == (b.height() + 1) / 2 &&
        source.width() < b.width())
        upsampled = pointUpsample(source, b.width(), b.height());
    const Image& a = upsampled ? *upsampled : source;
    const Texture* sigma = ctx.input(kReferenceStdErr);
    const Texture* depth = ctx.input(gbuffer::kDepth);
    std::optional<Image> mask;
    if (depth) {
        const float sky = mParams.skyDistance > 0.0f ? mParams.skyDistance
                                                     : std::numeric_limits<float>::infinity();
        mask = notSkyMask(depth->image(), sky);
    }
    Image absError(a.width(), a.height(), {"Y"});
    ErrorInputs in;
    in.result = &a;
    in.reference = &b;
    in.referenceStdErr = sigma ? &sigma->image() : nullptr;
    in.mask = mask ? &*mask : nullptr;
    in.tolerance = mParams.tolerance;
    const ErrorStats s = measureError(in, &absError);

    for (const auto& [name, value] : s.figures())
        ctx.addMetric(name, value);
    ctx.addWork("pixels", s.pixels);
    ctx.addWork("skippedPixels", s.maskedPixels);

    if (ctx.isRequested(kHeat)) {
        const float scale =
            mParams.heatScale > 0.0f ? mParams.heatScale : heatScale(absError, in.mask);
        ctx.output(kHeat, {{a.width(), a.height()}}).image() = heatmap(absError, in.mask, scale);
        ctx.addMetric("heatScale", scale);
    }
    if (ctx.isRequested(kAbsError))
        ctx.output(kAbsError, {{a.width(), a.height()}}).image() = std::move(absError);
}

}  // namespace fp
