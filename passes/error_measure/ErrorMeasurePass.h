#pragma once
// Error as a pass (Falcor's ErrorMeasurePass): compares any pass output with a reference inside
// the chain — typically a Truth.* layer of the capture — so `framepass run` and `framepass bench`
// report error next to time. The statistics (ErrorMetrics.h) go into the run report as metrics;
// the outputs are a heat map for people and the per-pixel |error| for tools.
#include "passes/core/Params.h"
#include "passes/core/Pass.h"

#include <limits>

namespace fp {

struct ErrorMeasureParams {
    float tolerance = 0.1f;    //!< over tolerance when |a−b| > tolerance·(|b| + 0.01), [0, 1e6]
    float skyDistance = 0.0f;  //!< depths ≥ this are sky and left out; 0 = only +inf depths
    float heatScale = 0.0f;    //!< |error| at the top of the heat map; 0 = 99th percentile
    float maxRoughness = 0.0f;  //!< > 0: only pixels at most this rough are measured
};

struct ErrorStats;

class ErrorMeasurePass final : public Pass {
public:
    using Params = ErrorMeasureParams;
    static ParamSpec<Params> paramSpec();
    explicit ErrorMeasurePass(const Params& params) : mParams(params) {}

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

#if FP_HAVE_CUDA
    bool hasCudaKernel() const override { return true; }
    void executeCuda(PassContext& ctx) override;  // ErrorMeasurePass.cu
#endif

    static constexpr const char* kSource = "source";
    static constexpr const char* kReference = "reference";
    static constexpr const char* kReferenceStdErr = "referenceStdErr";
    static constexpr const char* kHeat = "heat";
    static constexpr const char* kRoughness = "roughness";
    static constexpr const char* kAbsError = "absError";

    /// A half-resolution source (a half-res SSGI trace) is measured as the 4.27 composite reads
    /// it: point-upsampled, full-res pixel (x, y) taking texel (x/2, y/2).
    static bool isHalfResolution(Extent source, Extent reference) {
        return source.width == (reference.width + 1) / 2 &&
               source.height == (reference.height + 1) / 2 && source.width < reference.width;
    }

    /// The depth at and beyond which a pixel is sky for a `skyDistance` parameter (0: +inf only).
    static float skyDepthFor(float skyDistance) {
        return skyDistance > 0.0f ? skyDistance : std::numeric_limits<float>::infinity();
    }

private:
    /// Depths at or beyond this are sky.
    float skyDepth() const { return skyDepthFor(mParams.skyDistance); }
    /// The figures and work counts into the run report.
    void reportStats(PassContext& ctx, const ErrorStats& s) const;

    Params mParams;
};

}  // namespace fp
