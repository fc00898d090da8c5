#pragma once
// Error as a pass (Falcor's ErrorMeasurePass): compares any pass output with a reference inside
// the chain — typically a Truth.* layer of the capture — so `framepass run` and `framepass bench`
// report error next to time. The statistics (ErrorMetrics.h) go into the run report as metrics;
// the outputs are a heat map for people and the per-pixel |error| for tools.
#include "passes/core/Params.h"
#include "passes/core/Pass.h"

namespace fp {

struct ErrorMeasureParams {
    float tolerance = 0.1f;    //!< over tolerance when |a−b| > tolerance·(|b| + 0.01), [0, 1e6]
    float skyDistance = 0.0f;  //!< depths ≥ this are sky and left out; 0 = only +inf depths
    float heatScale = 0.0f;    //!< |error| at the top of the heat map; 0 = 99th percentile
};

class ErrorMeasurePass final : public Pass {
public:
    using Params = ErrorMeasureParams;
    static ParamSpec<Params> paramSpec();
    explicit ErrorMeasurePass(const Params& params) : mParams(params) {}

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

private:
    Params mParams;
};

}  // namespace fp
