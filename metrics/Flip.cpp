#include "metrics/Flip.h"

#include "foundation/Error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace fp {

namespace {

constexpr double kPi = 3.14159265358979323846;

// One channel of the frame, row-major, and an image of three.
struct Plane1 {
    int width = 0, height = 0;
    std::vector<float> v;
    Plane1(int w, int h) : width(w), height(h), v(std::size_t(w) * std::size_t(h), 0.0f) {}
    float& at(int x, int y) { return v[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
    float at(int x, int y) const { return v[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};
using Plane3 = std::array<Plane1, 3>;

Plane3 plane3(int w, int h) { return {Plane1(w, h), Plane1(w, h), Plane1(w, h)}; }

template <class F>
void forRows(int height, const F& f) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) f(y);
    });
}

// `in` correlated with kx along rows and then ky along columns (both of odd length, centred),
// the border replicated: a separable 2D filter. Each row is first copied with its replicated
// border and each output row summed over whole input rows, so both inner loops run over
// consecutive pixels and vectorise.
Plane1 separable(const Plane1& in, const std::vector<float>& kx, const std::vector<float>& ky) {
    const int w = in.width, h = in.height;
    const int rx = int(kx.size() / 2), ry = int(ky.size() / 2);
    Plane1 rows(w, h), out(w, h);
    forRows(h, [&](int y) {
        std::vector<float> padded(std::size_t(w + 2 * rx));
        const float* src = &in.v[std::size_t(y) * std::size_t(w)];
        for (int x = -rx; x < w + rx; ++x) padded[std::size_t(x + rx)] = src[std::clamp(x, 0, w - 1)];
        float* dst = &rows.v[std::size_t(y) * std::size_t(w)];
        for (int x = 0; x < w; ++x) dst[x] = 0.0f;
        for (std::size_t i = 0; i < kx.size(); ++i) {
            const float k = kx[i];
            const float* p = padded.data() + i;
            for (int x = 0; x < w; ++x) dst[x] += k * p[x];
        }
    });
    forRows(h, [&](int y) {
        float* dst = &out.v[std::size_t(y) * std::size_t(w)];
        for (int x = 0; x < w; ++x) dst[x] = 0.0f;
        for (int i = -ry; i <= ry; ++i) {
            const float k = ky[std::size_t(i + ry)];
            const float* p = &rows.v[std::size_t(std::clamp(y + i, 0, h - 1)) * std::size_t(w)];
            for (int x = 0; x < w; ++x) dst[x] += k * p[x];
        }
    });
    return out;
}

// sRGB's transfer curve, decoding.
float srgbToLinear(float c) {
    return c > 0.04045f ? std::pow((c + 0.055f) / 1.055f, 2.4f) : c / 12.92f;
}

// Linear sRGB (Rec. 709 primaries) → CIE XYZ under D65, in the exact fractions of the sRGB
// primaries and white point, its inverse, and D65's white (the matrix's row sums).
constexpr double kRgbToXyz[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
constexpr double kXyzToRgb[3][3] = {{3.241003275, -1.537398934, -0.498615861},
                                    {-0.969224334, 1.875930071, 0.041554224},
                                    {0.055639423, -0.204011202, 1.057148933}};
constexpr double kWhite[3] = {0.950428545, 1.0, 1.088900371};

std::array<float, 3> mul(const double m[3][3], const std::array<float, 3>& v) {
    return {float(m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2]),
            float(m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2]),
            float(m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2])};
}

// YCxCz, the linear opponent space of CIELAB without its cube root (Y: 116·Y/Yn − 16).
std::array<float, 3> linearToYcxcz(const std::array<float, 3>& rgb) {
    const auto xyz = mul(kRgbToXyz, rgb);
    const float x = float(xyz[0] / kWhite[0]), y = xyz[1], z = float(xyz[2] / kWhite[2]);
    return {116.0f * y - 16.0f, 500.0f * (x - y), 200.0f * (y - z)};
}
std::array<float, 3> ycxczToLinear(const std::array<float, 3>& o) {
    const float y = (o[0] + 16.0f) / 116.0f;
    const std::array<float, 3> xyz = {float((y + o[1] / 500.0f) * kWhite[0]), y,
                                      float((y - o[2] / 200.0f) * kWhite[2])};
    return mul(kXyzToRgb, xyz);
}

// CIELAB of linear RGB, then the Hunt adjustment: chroma scaled by L/100 (colours darken
// towards grey).
std::array<float, 3> huntLab(const std::array<float, 3>& rgb) {
    const auto xyz = mul(kRgbToXyz, rgb);
    auto f = [](double t) {
        constexpr double d = 6.0 / 29.0;
        return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
    };
    const double fx = f(xyz[0] / kWhite[0]), fy = f(xyz[1]), fz = f(xyz[2] / kWhite[2]);
    const double l = 116 * fy - 16;
    return {float(l), float(0.01 * l * 500 * (fx - fy)), float(0.01 * l * 200 * (fy - fz))};
}

float hyab(const std::array<float, 3>& a, const std::array<float, 3>& b) {
    const float dl = a[0] - b[0], da = a[1] - b[1], db = a[2] - b[2];
    return std::fabs(dl) + std::sqrt(da * da + db * db);
}

// The contrast sensitivity of one opponent channel as a spatial filter: a1·√(π/b1)·e^(−π²r²/b1)
// + a2·√(π/b2)·e^(−π²r²/b2), r in degrees, over a square of radius 3·√(b/(2π²)) degrees for the
// widest b of the three channels, normalised to sum to 1. Each Gaussian is separable; the filter
// is their weighted sum, applied as two separable passes.
struct Csf {
    double a1, b1, a2, b2;
};
constexpr Csf kAchromatic{1, 0.0047, 0, 1e-5}, kRedGreen{1, 0.0053, 0, 1e-5},
    kBlueYellow{34.1, 0.04, 13.5, 0.025};

Plane1 csfFilter(const Plane1& in, const Csf& csf, double ppd) {
    const int r = int(std::ceil(3 * std::sqrt(kBlueYellow.b1 / (2 * kPi * kPi)) * ppd));
    const double dx = 1.0 / ppd;
    auto gaussian = [&](double b, double& sum) {
        std::vector<float> g(std::size_t(2 * r + 1));
        sum = 0;
        for (int i = -r; i <= r; ++i) {
            const double v = std::exp(-kPi * kPi * (i * dx) * (i * dx) / b);
            g[std::size_t(i + r)] = float(v);
            sum += v;
        }
        return g;
    };
    double s1 = 0, s2 = 0;
    const auto g1 = gaussian(csf.b1, s1), g2 = gaussian(csf.b2, s2);
    const double w1 = csf.a1 * std::sqrt(kPi / csf.b1), w2 = csf.a2 * std::sqrt(kPi / csf.b2);
    const double total = w1 * s1 * s1 + w2 * s2 * s2;  // the 2D filter's sum
    Plane1 out = separable(in, g1, g1);
    const float k1 = float(w1 / total);
    if (csf.a2 == 0) {
        for (float& v : out.v) v *= k1;
        return out;
    }
    const Plane1 second = separable(in, g2, g2);
    const float k2 = float(w2 / total);
    for (std::size_t i = 0; i < out.v.size(); ++i) out.v[i] = k1 * out.v[i] + k2 * second.v[i];
    return out;
}

// The edge (first derivative) or point (second derivative) detector of a Gaussian with a peak
// to trough of 0.082°, its positive weights summing to 1 and its negative ones to −1: separable
// as the derivative along one axis times the Gaussian along the other.
std::pair<std::vector<float>, std::vector<float>> featureKernels(double ppd, bool points) {
    const double sd = 0.5 * 0.082 * ppd;
    const int r = int(std::ceil(3 * sd));
    std::vector<double> d(std::size_t(2 * r + 1)), g(d.size());
    double positive = 0, negative = 0, gsum = 0;
    for (int i = -r; i <= r; ++i) {
        const double e = std::exp(-double(i) * i / (2 * sd * sd));
        const double v = points ? (double(i) * i / (sd * sd) - 1) * e : -double(i) * e;
        d[std::size_t(i + r)] = v;
        g[std::size_t(i + r)] = e;
        (v > 0 ? positive : negative) += v;
        gsum += e;
    }
    std::vector<float> across(d.size()), along(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
        across[i] = float(d[i] > 0 ? d[i] / positive : d[i] / -negative);
        along[i] = float(g[i] / gsum);
    }
    return {across, along};
}

// ‖(∂x, ∂y)‖ of the feature detector over luminance `y`.
Plane1 featureMagnitude(const Plane1& y, double ppd, bool points) {
    const auto [across, along] = featureKernels(ppd, points);
    const Plane1 fx = separable(y, across, along), fy = separable(y, along, across);
    Plane1 out(y.width, y.height);
    for (std::size_t i = 0; i < out.v.size(); ++i) out.v[i] = std::hypot(fx.v[i], fy.v[i]);
    return out;
}

// LDR-FLIP of two images given as linear RGB in [0, 1] (the sRGB-encoded pictures it compares,
// decoded: HDR-FLIP's tone-mapped exposures need no round trip through the encoding).
Plane1 ldrFlip(const Plane3& reference, const Plane3& test, double ppd) {
    const int w = reference[0].width, h = reference[0].height;
    struct Prepared {
        Plane3 colour;  // Hunt-adjusted L*a*b* of the filtered image
        Plane1 edges, points;
    };
    auto prepare = [&](const Plane3& linear) {
        Plane3 opponent = plane3(w, h);
        Plane1 luminance(w, h);  // normalised Y, (Y* + 16) / 116
        forRows(h, [&](int y) {
            for (int x = 0; x < w; ++x) {
                const auto o = linearToYcxcz({linear[0].at(x, y), linear[1].at(x, y), linear[2].at(x, y)});
                for (int c = 0; c < 3; ++c) opponent[std::size_t(c)].at(x, y) = o[std::size_t(c)];
                luminance.at(x, y) = (o[0] + 16.0f) / 116.0f;
            }
        });
        Plane3 filtered = {csfFilter(opponent[0], kAchromatic, ppd),
                           csfFilter(opponent[1], kRedGreen, ppd),
                           csfFilter(opponent[2], kBlueYellow, ppd)};
        Plane3 lab = plane3(w, h);
        forRows(h, [&](int y) {
            for (int x = 0; x < w; ++x) {
                auto rgb = ycxczToLinear({filtered[0].at(x, y), filtered[1].at(x, y), filtered[2].at(x, y)});
                for (float& c : rgb) c = std::clamp(c, 0.0f, 1.0f);
                const auto l = huntLab(rgb);
                for (int c = 0; c < 3; ++c) lab[std::size_t(c)].at(x, y) = l[std::size_t(c)];
            }
        });
        return Prepared{std::move(lab), featureMagnitude(luminance, ppd, false),
                        featureMagnitude(luminance, ppd, true)};
    };
    const Prepared r = prepare(reference), t = prepare(test);
    constexpr float qc = 0.7f, qf = 0.5f, pc = 0.4f, pt = 0.95f;
    // The largest colour distance: pure green against pure blue.
    const float cmax = std::pow(hyab(huntLab({0, 1, 0}), huntLab({0, 0, 1})), qc);
    Plane1 out(w, h);
    forRows(h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const float de = std::pow(hyab({r.colour[0].at(x, y), r.colour[1].at(x, y), r.colour[2].at(x, y)},
                                           {t.colour[0].at(x, y), t.colour[1].at(x, y), t.colour[2].at(x, y)}),
                                      qc);
            const float colour = de < pc * cmax ? pt / (pc * cmax) * de
                                                : pt + (de - pc * cmax) / (cmax - pc * cmax) * (1 - pt);
            const float features =
                std::pow(std::max(std::fabs(r.edges.at(x, y) - t.edges.at(x, y)),
                                  std::fabs(r.points.at(x, y) - t.points.at(x, y))) /
                             std::sqrt(2.0f),
                         qf);
            out.at(x, y) = std::pow(colour, 1 - features);
        }
    });
    return out;
}

// ACES filmic curve (Narkowicz's fit) with its 0.6 pre-exposure folded in, as HDR-FLIP uses it.
constexpr double kAces[6] = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};

float acesToneMap(float x) {
    const double v = x, num = kAces[0] * v * v + kAces[1] * v + kAces[2],
                 den = kAces[3] * v * v + kAces[4] * v + kAces[5];
    return std::isfinite(den) ? float(std::clamp(num / den, 0.0, 1.0)) : 1.0f;
}

// The value the curve maps to t: the positive root of (k0 − k3·t)x² + (k1 − k4·t)x + (k2 − k5·t).
double acesInverse(double t) {
    const double c0 = (kAces[1] - kAces[4] * t) / (kAces[0] - kAces[3] * t);
    const double c1 = (kAces[2] - kAces[5] * t) / (kAces[0] - kAces[3] * t);
    return -0.5 * c0 + std::sqrt(0.25 * c0 * c0 - c1);
}

}  // namespace

FlipResult flip(const Image& reference, const Image& test, const Image* mask,
                const FlipOptions& options, Image* errorMap) {
    const int w = reference.width(), h = reference.height(), channels = reference.channelCount();
    if (test.width() != w || test.height() != h || test.channelCount() != channels)
        throw UsageError(fmt::format("FLIP: the test is {}×{} with {} channels, the reference "
                                     "{}×{} with {}",
                                     test.width(), test.height(), test.channelCount(), w, h,
                                     channels));
    if (channels != 1 && channels != 3 && channels != 4)
        throw UsageError(fmt::format("FLIP compares colours: 1 (grey), 3 or 4 channels, not {}",
                                     channels));
    if (mask && (mask->width() != w || mask->height() != h))
        throw UsageError("FLIP: the mask's size is not the images'");
    FlipResult result;
    result.hdr = options.hdr;
    // RGB of both, a grey image as three equal channels; a pixel with a NaN or an infinity is
    // black here and has error 1 (it is as wrong as a pixel can be).
    std::vector<uint8_t> nonFinite(std::size_t(w) * std::size_t(h), 0);
    auto rgbOf = [&](const Image& image) {
        Plane3 out = plane3(w, h);
        for (int c = 0; c < 3; ++c) {
            const Plane& p = image.plane(channels == 1 ? 0 : c);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const float v = p.at(x, y);
                    if (!std::isfinite(v)) nonFinite[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1;
                    out[std::size_t(c)].at(x, y) = std::isfinite(v) ? v : 0.0f;
                }
        }
        return out;
    };
    const Plane3 ref = rgbOf(reference), tst = rgbOf(test);
    auto kept = [&](int x, int y) { return !mask || mask->plane(0).at(x, y) > 0.0f; };

    Plane1 error(w, h);
    const double ppd = options.pixelsPerDegree;
    if (!options.hdr) {
        Plane3 r = ref, t = tst;
        for (auto* image : {&r, &t})
            for (Plane1& p : *image)
                for (float& v : p.v) v = srgbToLinear(std::clamp(v, 0.0f, 1.0f));
        error = ldrFlip(r, t, ppd);
    } else {
        double start = options.startExposure, stop = options.stopExposure;
        int count = options.exposures;
        if (count <= 0) {
            // From the reference's luminance over the measured pixels: the brightest mapped to
            // 0.85 at the first exposure, the median (of the positive ones, if it is 0) at the last.
            std::vector<float> lum;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    if (kept(x, y))
                        lum.push_back(std::max(0.0f, 0.2126f * ref[0].at(x, y) + 0.7152f * ref[1].at(x, y) +
                                                         0.0722f * ref[2].at(x, y)));
            const float brightest = lum.empty() ? 0.0f : *std::max_element(lum.begin(), lum.end());
            if (brightest > 0) {
                std::vector<float> positive;
                for (float l : lum)
                    if (l > 0) positive.push_back(l);
                auto median = [](std::vector<float> v) {  // of an even count: the middle two's mean
                    const std::size_t m = v.size() / 2;
                    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(m), v.end());
                    const float upper = v[m];
                    if (v.size() % 2) return upper;
                    return 0.5f * (upper + *std::max_element(v.begin(), v.begin() + std::ptrdiff_t(m)));
                };
                float mid = median(lum);
                if (!(mid > 0)) mid = median(positive);
                start = std::log2(acesInverse(0.85) / brightest);
                stop = std::log2(acesInverse(0.85) / mid);
            }
            count = std::max(2, int(std::ceil(stop - start)));
        }
        const double step = (stop - start) / std::max(count - 1, 1);
        for (int i = 0; i < count; ++i) {
            const float scale = float(std::exp2(start + i * step));
            auto exposed = [&](const Plane3& in) {
                Plane3 out = plane3(w, h);
                for (std::size_t c = 0; c < 3; ++c)
                    for (std::size_t k = 0; k < in[c].v.size(); ++k)
                        out[c].v[k] = acesToneMap(std::max(in[c].v[k], 0.0f) * scale);
                return out;
            };
            const Plane1 e = ldrFlip(exposed(ref), exposed(tst), ppd);
            for (std::size_t k = 0; k < e.v.size(); ++k) error.v[k] = std::max(error.v[k], e.v[k]);
        }
        result.startExposure = start;
        result.stopExposure = stop;
        result.exposures = count;
    }

    double sum = 0;
    if (errorMap) *errorMap = Image(w, h, {"Y"});
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float& e = error.at(x, y);
            if (!kept(x, y)) {
                e = 0;
            } else {
                if (nonFinite[std::size_t(y) * std::size_t(w) + std::size_t(x)]) {
                    e = 1;
                    ++result.nonFinitePixels;
                }
                sum += e;
                ++result.pixels;
            }
            if (errorMap) errorMap->plane(0).at(x, y) = e;
        }
    result.mean = result.pixels ? sum / double(result.pixels) : 0.0;
    return result;
}

}  // namespace fp
