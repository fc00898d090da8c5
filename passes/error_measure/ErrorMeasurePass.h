#pragma once
// Error as a pass (Falcor's ErrorMeasurePass): compares any pass output with a reference inside
// the chain — typically a Truth.* layer of the capture — so `framepass run` and `framepass bench`
// report error next to time. The statistics (ErrorMetrics.h) go into the run report as metrics;
// the outputs are a heat map for people and the per-pixel |error| for tools.
#include "passes/core/Params.h"
#include "passes/core/Pass.h"
#include "passes/metrics/ErrorMetrics.h"

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

private:
    /// Depths at or beyond this are sky.
    float skyDepth() const { return skyDepthFor(mParams.skyDistance); }
    /// The figures and work counts into the run report.
    void reportStats(PassContext& ctx, const ErrorStats& s) const;

    Params mParams;
};

}  // namespace fp
