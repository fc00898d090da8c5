#pragma once
// Error as a pass (Falcor's ErrorMeasurePass): compares any pass output with a reference inside
// the chain — typically a Truth.* layer of the capture — so `framepass run` and `framepass bench`
// report error next to time. The statistics (ErrorMetrics.h) go into the run report as metrics;
// the outputs are a heat map for people and the per-pixel |error| for tools.
#include "framework/Params.h"
#include "framework/Pass.h"
#include "metrics/ErrorMetrics.h"
#include "metrics/Flip.h"
#include "passes/error_measure/ErrorMask.h"

#include <limits>
#include <string>

namespace fp {

struct ErrorMeasureParams {
    float tolerance = 0.1f;    //!< over tolerance when |a−b| > tolerance·(|b| + 0.01), [0, 1e6]
    float skyDistance = 0.0f;  //!< depths ≥ this are sky and left out; 0 = only +inf depths
    float heatScale = 0.0f;    //!< |error| at the top of the heat map; 0 = 99th percentile
    float maxRoughness = 0.0f;  //!< > 0: only pixels at most this rough are measured
    float excludeAbove = 0.0f;  //!< with input `exclude`: pixels where it is above this are left out
    std::string flip = "off";   //!< FLIP beside the figures: off, hdr (linear) or ldr (display-referred)
    float flipPixelsPerDegree = float(kFlipDefaultPixelsPerDegree);  //!< FLIP's observer
};

struct ErrorStats;

class ErrorMeasurePass final : public PassWithParams<ErrorMeasureParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;
    PassMemory memoryBytes(Extent frame) const override;

#if FP_HAVE_CUDA
    // ErrorMeasurePass.cu. FLIP is taken on the host: with it, the pass runs on the CPU.
    bool hasCudaKernel() const override { return mParams.flip == "off"; }
    void executeCuda(PassContext& ctx) override;
#endif

    static constexpr const char* kSource = "source";
    static constexpr const char* kReference = "reference";
    static constexpr const char* kReferenceStdErr = "referenceStdErr";
    static constexpr const char* kHeat = "heat";
    static constexpr const char* kRoughness = "roughness";
    static constexpr const char* kExclude = "exclude";
    static constexpr const char* kAbsError = "absError";
    static constexpr const char* kFlip = "flip";

private:
    /// Depths at or beyond this are sky.
    float skyDepth() const { return skyDepthFor(mParams.skyDistance); }
    /// The mask's thresholds; each device binds its planes.
    ErrorMask maskThresholds() const {
        ErrorMask m;
        m.skyDepth = skyDepth();
        m.maxRoughness = mParams.maxRoughness;
        m.excludeAbove = mParams.excludeAbove;
        return m;
    }
    /// The figures and work counts into the run report.
    void reportStats(PassContext& ctx, const ErrorStats& s) const;

};

}  // namespace fp
