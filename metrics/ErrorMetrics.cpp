#include "metrics/ErrorMetrics.h"

#include "foundation/Error.h"
#include "foundation/Tiles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace fp {

std::map<std::string, double> ErrorStats::figures() const {
    std::map<std::string, double> f = {{"rmse", rmse}, {"relMse", relMse},     {"smape", smape},
                                       {"mae", mae},   {"bias", bias},         {"maxError", maxError},
                                       {"overTolerance", overTolerance}};
    if (noiseRmse) f["referenceNoiseRmse"] = *noiseRmse;
    return f;
}

nlohmann::json ErrorStats::toJson() const {
    nlohmann::json j = figures();
    j["pixels"] = pixels;
    j["maskedPixels"] = maskedPixels;
    j["tolerance"] = tolerance;
    j["nonFinitePixels"] = nonFinitePixels;
    // JSON has no infinity: a max error made infinite by a NaN or inf pixel is null.
    if (!std::isfinite(maxError)) j["maxError"] = nullptr;
    if (noiseRmse) j["noiseLimited"] = noiseLimited();
    return j;
}

ErrorStats measureError(const ErrorInputs& in, Image* absError) {
    const Image& a = *in.result;
    const Image& b = *in.reference;
    const Image* s = in.referenceStdErr;
    ErrorPixelInputs pin = errorPixelInputs(a, b, s, in.tolerance, in.halfSource);
    if (in.mask)
        pin.mask = viewOf(in.mask->plane(0));
    const int W = b.width(), H = b.height();
    const int tilesX = (W + kTileSize - 1) / kTileSize;
    // Sums per tile, combined in tile order afterwards so the result does not depend on which
    // thread finished first (floating-point addition is not associative).
    std::vector<ErrorSums> tiles(std::size_t(tilesX) * ((H + kTileSize - 1) / kTileSize));
    forEachTile(W, H, [&](const Tile& t) {
        ErrorSums& sum = tiles[std::size_t(t.y0 / kTileSize) * tilesX + t.x0 / kTileSize];
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const float e = measurePixel(pin, x, y, sum);
                if (absError)
                    absError->plane(0).at(x, y) = e;
            }
    });
    ErrorSums total;
    for (const ErrorSums& t : tiles)
        total.add(t);
    return finishError(total, in.tolerance, s != nullptr);
}

void checkComparable(ImageShape result, ImageShape reference, const ImageShape* stdErr,
                     bool halfSource) {
    const bool sizesMatch = halfSource ? result.width == (reference.width + 1) / 2 &&
                                             result.height == (reference.height + 1) / 2
                                       : result.width == reference.width &&
                                             result.height == reference.height;
    FP_CHECK(sizesMatch,
             "result is {}×{} but the reference is {}×{}", result.width, result.height,
             reference.width, reference.height);
    FP_CHECK(result.channels == reference.channels,
             "result has {} channels but the reference has {}", result.channels,
             reference.channels);
    FP_CHECK(!stdErr || (stdErr->width == reference.width && stdErr->height == reference.height &&
                         stdErr->channels == reference.channels),
             "the reference's standard error does not match the reference's size");
    FP_CHECK(result.channels <= ErrorPixelInputs::kMaxChannels,
             "error_measure compares 1 to {} channels; the result has {}",
             ErrorPixelInputs::kMaxChannels, result.channels);
}

ErrorStats finishError(const ErrorSums& total, double tolerance, bool hasSigma) {
    ErrorStats r;
    r.pixels = total.pixels;
    r.maskedPixels = total.masked;
    r.tolerance = tolerance;
    r.nonFinitePixels = total.nonFinite;
    if (total.pixels > 0) r.overTolerance = double(total.over) / double(total.pixels);
    if (total.nonFinite > 0) r.maxError = std::numeric_limits<double>::infinity();
    if (total.values == 0) return r;
    const double n = double(total.values);
    r.rmse = std::sqrt(total.sq / n);
    r.relMse = total.rel / n;
    r.smape = total.smape / n;
    r.mae = total.abs / n;
    r.bias = total.bias / n;
    if (total.nonFinite == 0) r.maxError = total.max;
    if (hasSigma) r.noiseRmse = std::sqrt(total.noise / n);
    return r;
}

Image notSkyMask(const Image& sceneDepth, float skyDistance) {
    Image mask(sceneDepth.width(), sceneDepth.height(), {"Y"});
    forEachTile(mask.width(), mask.height(), [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                mask.plane(0).at(x, y) = isNotSky(sceneDepth.plane(0).at(x, y), skyDistance);
            }
    });
    return mask;
}

double medianRelativeStdErr(const Image& mean, const Image& stdErr, const Image* mask) {
    std::vector<double> rel;
    for (int y = 0; y < mean.height(); ++y)
        for (int x = 0; x < mean.width(); ++x) {
            if (mask && !(mask->plane(0).at(x, y) > 0.0f)) continue;
            double m2 = 0, s2 = 0;
            for (int c = 0; c < mean.channelCount(); ++c) {
                m2 += double(mean.plane(c).at(x, y)) * mean.plane(c).at(x, y);
                s2 += double(stdErr.plane(c).at(x, y)) * stdErr.plane(c).at(x, y);
            }
            if (m2 > 0.0) rel.push_back(std::sqrt(s2 / m2));
        }
    if (rel.empty()) return std::numeric_limits<double>::quiet_NaN();
    auto mid = rel.begin() + rel.size() / 2;
    std::nth_element(rel.begin(), mid, rel.end());
    return *mid;
}

}  // namespace fp
