#pragma once
// Error of an image against a reference, over the pixels that matter (docs/design.md, Truth and evaluation). With N the
// number of (pixel, channel) values in the mask, e = a − b and ε = 0.01 (the usual guard of
// relative metrics against dark pixels):
//   RMSE   √(Σe²/N)            relMSE  Σ e²/(b² + ε) / N        SMAPE  Σ 2|e|/(|a| + |b|) / N
//   MAE    Σ|e|/N              bias    Σe/N                     max    max|e|
//   overTolerance  fraction of pixels whose largest |e| exceeds tolerance·(|b| + ε)
// When the reference carries its standard error σ (a Truth.*.StdErr layer), `noiseRmse` =
// √(Σσ²/N) is the RMSE that a perfect result would still show against this reference: the floor
// below which a comparison says nothing.
#include "foundation/HostDevice.h"
#include "foundation/Image.h"
#include "foundation/PlaneView.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>

namespace fp {

inline constexpr double kRelativeEpsilon = 0.01;

/// A half-resolution source (a half-res SSGI trace) is measured as the 4.27 composite reads it:
/// point-upsampled, full-res pixel (x, y) taking texel (x/2, y/2).
inline bool isHalfResolution(Extent source, Extent reference) {
    return source.width == (reference.width + 1) / 2 &&
           source.height == (reference.height + 1) / 2 && source.width < reference.width;
}

/// The depth at and beyond which a pixel is sky for a `skyDistance` parameter (0: +inf only).
inline float skyDepthFor(float skyDistance) {
    return skyDistance > 0.0f ? skyDistance : std::numeric_limits<float>::infinity();
}

struct ErrorStats {
    uint64_t pixels = 0;         //!< pixels compared (inside the mask)
    uint64_t maskedPixels = 0;   //!< pixels left out (sky)
    double rmse = 0, relMse = 0, smape = 0, mae = 0, bias = 0, maxError = 0;
    double overTolerance = 0;
    double tolerance = 0;
    /// Pixels where A or B holds a NaN or an infinity: each is over any tolerance and makes
    /// `maxError` +inf (null in JSON); the other figures are over the finite pixels only.
    uint64_t nonFinitePixels = 0;
    std::optional<double> noiseRmse;  //!< the reference's own noise, when known

    /// True when the measured error is within twice the reference's noise.
    bool noiseLimited() const { return noiseRmse && rmse <= 2.0 * *noiseRmse; }
    /// The figures by name (rmse, relMse, ..., referenceNoiseRmse when known): what compare's
    /// JSON and error_measure's report share.
    std::map<std::string, double> figures() const;
    nlohmann::json toJson() const;
};

struct ErrorInputs {
    const Image* result = nullptr;     //!< a
    const Image* reference = nullptr;  //!< b, same size and channel count
    const Image* referenceStdErr = nullptr;  //!< σ of b, optional
    const Image* mask = nullptr;       //!< 1 channel, > 0 = compare this pixel; null = all
    double tolerance = 0.1;
    /// The result is at half the reference's resolution (⌈W/2⌉ × ⌈H/2⌉) and is measured
    /// point-upsampled, as ErrorPixelInputs::halfSource reads it.
    bool halfSource = false;
};

/// Size and channel count of an image about to be compared (host or device).
struct ImageShape {
    int width, height, channels;
};

/// Checks that a result (point-upsampled when `halfSource`), a reference and its standard error
/// (nullptr: none) can be compared; fp::Error says why not.
void checkComparable(ImageShape result, ImageShape reference, const ImageShape* stdErr,
                     bool halfSource);

/// Running sums of a region of pixels. The CPU sums each 64×64 tile and then the tiles in order;
/// the GPU sums each row of a tile in lanes (ErrorMeasurePass.cu): the same per-value terms, added
/// in another order.
struct ErrorSums {
    unsigned long long pixels = 0, masked = 0, values = 0, over = 0, nonFinite = 0;
    double sq = 0, rel = 0, smape = 0, abs = 0, bias = 0, max = 0, noise = 0;

    FP_HD void add(const ErrorSums& o) {
        pixels += o.pixels;
        masked += o.masked;
        values += o.values;
        over += o.over;
        nonFinite += o.nonFinite;
        sq += o.sq;
        rel += o.rel;
        smape += o.smape;
        abs += o.abs;
        bias += o.bias;
        max = max < o.max ? o.max : max;  // std::max's order
        noise += o.noise;
    }
};

/// One pixel's planes as per-pixel code reads them (either backend). `mask` and `sigma` have
/// null data when absent; `halfSource`: the result is at half resolution and pixel (x, y) reads
/// its texel (x/2, y/2), as the 4.27 composite point-upsamples a half-resolution trace.
struct ErrorPixelInputs {
    static constexpr int kMaxChannels = 4;
    PlaneView a[kMaxChannels], b[kMaxChannels], sigma[kMaxChannels], mask;
    int channels = 0;
    bool halfSource = false;
    double tolerance = 0.1;
};

/// Adds pixel (x, y) to `sum` and returns its mean |e| over the channels (0 outside the mask).
/// A pixel with a NaN or an infinity in A or B is counted apart (`nonFinite`), over tolerance,
/// left out of the sums (one NaN would make every figure NaN) and returned as +inf.
FP_HD inline float measurePixel(const ErrorPixelInputs& in, int x, int y, ErrorSums& sum) {
    if (in.mask.data && !(in.mask.at(x, y) > 0.0f)) {
        ++sum.masked;
        return 0.0f;
    }
    ++sum.pixels;
    const int ax = in.halfSource ? x / 2 : x, ay = in.halfSource ? y / 2 : y;
    for (int c = 0; c < in.channels; ++c)
        if (!std::isfinite(in.a[c].at(ax, ay)) || !std::isfinite(in.b[c].at(x, y))) {
            ++sum.nonFinite;
            ++sum.over;
            return INFINITY;
        }
    double pixelAbs = 0;
    bool over = false;
    for (int c = 0; c < in.channels; ++c) {
        const double av = in.a[c].at(ax, ay), bv = in.b[c].at(x, y);
        const double e = av - bv, ae = e < 0 ? -e : e;
        sum.sq += e * e;
        sum.rel += e * e / (bv * bv + kRelativeEpsilon);
        const double denom = (av < 0 ? -av : av) + (bv < 0 ? -bv : bv);
        sum.smape += denom > 0.0 ? 2.0 * ae / denom : 0.0;
        sum.abs += ae;
        sum.bias += e;
        sum.max = sum.max < ae ? ae : sum.max;  // std::max's order
        if (in.sigma[c].data) {
            const double sigma = in.sigma[c].at(x, y);
            sum.noise += sigma * sigma;
        }
        over = over || ae > in.tolerance * ((bv < 0 ? -bv : bv) + kRelativeEpsilon);
        pixelAbs += ae;
    }
    sum.values += (unsigned long long)in.channels;
    sum.over += over ? 1 : 0;
    return float(pixelAbs / in.channels);
}

/// measurePixel's inputs for result `a`, reference `b` and b's standard error (nullptr: none),
/// host Images or device images alike, after checkComparable; the caller sets the mask.
template <class ImageT>
ErrorPixelInputs errorPixelInputs(const ImageT& a, const ImageT& b, const ImageT* sigma,
                                  double tolerance, bool halfSource) {
    const ImageShape sigmaShape =
        sigma ? ImageShape{sigma->width(), sigma->height(), sigma->channelCount()} : ImageShape{};
    checkComparable({a.width(), a.height(), a.channelCount()},
                    {b.width(), b.height(), b.channelCount()}, sigma ? &sigmaShape : nullptr,
                    halfSource);
    ErrorPixelInputs in;
    in.channels = a.channelCount();
    in.tolerance = tolerance;
    in.halfSource = halfSource;
    for (int c = 0; c < in.channels; ++c) {
        in.a[c] = viewOf(a.plane(c));
        in.b[c] = viewOf(b.plane(c));
        if (sigma)
            in.sigma[c] = viewOf(sigma->plane(c));
    }
    return in;
}

/// The figures of the summed pixels.
ErrorStats finishError(const ErrorSums& total, double tolerance, bool hasSigma);

/// Computes the statistics; if `absError` is given it receives the per-pixel mean |e| over the
/// channels (0 outside the mask), same size, 1 channel.
ErrorStats measureError(const ErrorInputs& in, Image* absError = nullptr);

/// A pixel of view depth `depth` is compared (not sky): finite and nearer than `skyDistance`.
FP_HD inline float isNotSky(float depth, float skyDistance) {
    return std::isfinite(depth) && depth < skyDistance ? 1.0f : 0.0f;
}

/// Mask of the pixels that are not sky: finite depth below `skyDistance`.
Image notSkyMask(const Image& sceneDepth, float skyDistance);

/// Median over the pixels of the mask with a non-zero mean of ‖σ‖/‖mean‖ (L2 over channels):
/// how noisy a truth layer is, relative to its value. NaN when no pixel qualifies.
double medianRelativeStdErr(const Image& mean, const Image& stdErr, const Image* mask = nullptr);

}  // namespace fp
