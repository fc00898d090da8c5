#include "passes/metrics/ErrorMetrics.h"

#include "passes/core/Error.h"
#include "passes/core/Tiles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <vector>

namespace fp {

namespace {

// Sums of one tile, combined in tile order afterwards so the result does not depend on which
// thread finished first (floating-point addition is not associative).
struct Sums {
    uint64_t pixels = 0, masked = 0, values = 0, over = 0;
    double sq = 0, rel = 0, smape = 0, abs = 0, bias = 0, max = 0, noise = 0;
};

}  // namespace

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
    if (noiseRmse) j["noiseLimited"] = noiseLimited();
    return j;
}

ErrorStats measureError(const ErrorInputs& in, Image* absError) {
    const Image& a = *in.result;
    const Image& b = *in.reference;
    FP_CHECK(a.width() == b.width() && a.height() == b.height(),
             "result is {}×{} but the reference is {}×{}", a.width(), a.height(), b.width(),
             b.height());
    FP_CHECK(a.channelCount() == b.channelCount(),
             "result has {} channels but the reference has {}", a.channelCount(), b.channelCount());
    const Image* s = in.referenceStdErr;
    FP_CHECK(!s || (s->width() == b.width() && s->height() == b.height() &&
                    s->channelCount() == b.channelCount()),
             "the reference's standard error does not match the reference's size");
    const int C = a.channelCount(), W = a.width(), H = a.height();
    const int tilesX = (W + kTileSize - 1) / kTileSize;
    std::vector<Sums> tiles(std::size_t(tilesX) * ((H + kTileSize - 1) / kTileSize));

    forEachTile(W, H, [&](const Tile& t) {
        Sums& sum = tiles[std::size_t(t.y0 / kTileSize) * tilesX + t.x0 / kTileSize];
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                float* err = absError ? &absError->plane(0).at(x, y) : nullptr;
                if (in.mask && !(in.mask->plane(0).at(x, y) > 0.0f)) {
                    ++sum.masked;
                    if (err) *err = 0.0f;
                    continue;
                }
                ++sum.pixels;
                double pixelAbs = 0;
                bool over = false;
                for (int c = 0; c < C; ++c) {
                    const double av = a.plane(c).at(x, y), bv = b.plane(c).at(x, y);
                    const double e = av - bv, ae = std::abs(e);
                    sum.sq += e * e;
                    sum.rel += e * e / (bv * bv + kRelativeEpsilon);
                    const double denom = std::abs(av) + std::abs(bv);
                    sum.smape += denom > 0.0 ? 2.0 * ae / denom : 0.0;
                    sum.abs += ae;
                    sum.bias += e;
                    sum.max = std::max(sum.max, ae);
                    if (s) {
                        const double sigma = s->plane(c).at(x, y);
                        sum.noise += sigma * sigma;
                    }
                    over = over || ae > in.tolerance * (std::abs(bv) + kRelativeEpsilon);
                    pixelAbs += ae;
                }
                sum.values += uint64_t(C);
                sum.over += over ? 1 : 0;
                if (err) *err = float(pixelAbs / C);
            }
    });

    Sums total;
    for (const Sums& t : tiles) {
        total.pixels += t.pixels;
        total.masked += t.masked;
        total.values += t.values;
        total.over += t.over;
        total.sq += t.sq;
        total.rel += t.rel;
        total.smape += t.smape;
        total.abs += t.abs;
        total.bias += t.bias;
        total.max = std::max(total.max, t.max);
        total.noise += t.noise;
    }
    ErrorStats r;
    r.pixels = total.pixels;
    r.maskedPixels = total.masked;
    r.tolerance = in.tolerance;
    if (total.values == 0) return r;
    const double n = double(total.values);
    r.rmse = std::sqrt(total.sq / n);
    r.relMse = total.rel / n;
    r.smape = total.smape / n;
    r.mae = total.abs / n;
    r.bias = total.bias / n;
    r.maxError = total.max;
    r.overTolerance = double(total.over) / double(total.pixels);
    if (s) r.noiseRmse = std::sqrt(total.noise / n);
    return r;
}

Image notSkyMask(const Image& sceneDepth, float skyDistance) {
    Image mask(sceneDepth.width(), sceneDepth.height(), {"Y"});
    forEachTile(mask.width(), mask.height(), [&](const Tile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                const float d = sceneDepth.plane(0).at(x, y);
                mask.plane(0).at(x, y) = std::isfinite(d) && d < skyDistance ? 1.0f : 0.0f;
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
