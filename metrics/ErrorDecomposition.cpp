#include "metrics/ErrorDecomposition.h"

#include "foundation/Error.h"

#include <cmath>

namespace fp {

ErrorDecompositionStats decomposeError(const std::vector<LadderRung>& ladder, const Image* mask) {
    FP_CHECK(ladder.size() >= 2, "an error decomposition needs a result and a reference");
    for (const LadderRung& r : ladder)
        FP_CHECK(r.image != nullptr, "an error decomposition's rung has no image");
    const Image& reference = *ladder.back().image;
    FP_CHECK(!ladder.back().halfResolution, "the reference of a decomposition is at full size");
    const int W = reference.width(), H = reference.height(), C = reference.channelCount();
    for (std::size_t k = 0; k < ladder.size(); ++k) {
        const Image& img = *ladder[k].image;
        const int w = ladder[k].halfResolution ? (W + 1) / 2 : W;
        const int h = ladder[k].halfResolution ? (H + 1) / 2 : H;
        FP_CHECK(img.width() == w && img.height() == h && img.channelCount() == C,
                 "rung {} of the error decomposition is {}×{} with {} channels; the reference "
                 "is {}×{} with {}",
                 k, img.width(), img.height(), img.channelCount(), W, H, C);
    }
    FP_CHECK(!mask || (mask->width() == W && mask->height() == H),
             "the decomposition's mask is not the reference's size");

    const std::size_t steps = ladder.size() - 1;
    std::vector<double> sq(steps, 0.0), sum(steps, 0.0), along(steps, 0.0), v(ladder.size());
    double totalSq = 0, totalSum = 0;
    uint64_t values = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (mask && !(mask->plane(0).at(x, y) > 0.0f))
                continue;
            for (int c = 0; c < C; ++c) {
                for (std::size_t k = 0; k < ladder.size(); ++k) {
                    const bool half = ladder[k].halfResolution;
                    v[k] = ladder[k].image->plane(c).at(half ? x / 2 : x, half ? y / 2 : y);
                }
                // Differences of floats are exact in double, so the d_k add up to e exactly.
                const double e = v.front() - v.back();
                for (std::size_t k = 0; k < steps; ++k) {
                    const double d = v[k] - v[k + 1];
                    sq[k] += d * d;
                    sum[k] += d;
                    along[k] += d * e;
                }
                totalSq += e * e;
                totalSum += e;
                ++values;
            }
        }
    ErrorDecompositionStats r;
    r.values = values;
    r.steps.resize(steps);
    if (values == 0)
        return r;
    const double n = double(values);
    r.rmse = std::sqrt(totalSq / n);
    r.bias = totalSum / n;
    for (std::size_t k = 0; k < steps; ++k) {
        r.steps[k].rmse = std::sqrt(sq[k] / n);
        r.steps[k].bias = sum[k] / n;
        // With no error at all there is nothing to share out.
        r.steps[k].share = totalSq > 0 ? along[k] / totalSq : 0.0;
    }
    return r;
}

}  // namespace fp
