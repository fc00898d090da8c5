#pragma once
// Camera motion vectors: where each pixel's surface was on last frame's screen when only the
// camera moved (Unreal's velocity pass writes these for static geometry; moving objects add their
// own motion). For captures without a Velocity buffer, so the reduction and the SSGI denoiser can
// reproject through motion vectors as they do with Unreal's.
#include "passes/core/Params.h"
#include "passes/core/Pass.h"

namespace fp {

struct CameraVelocityParams {
    float skyDistance =
        0.0f;  //!< depths at or beyond this move as sky (rotation only); 0 = +inf only
};

class CameraVelocityPass final : public Pass {
public:
    using Params = CameraVelocityParams;
    static ParamSpec<Params> paramSpec();
    explicit CameraVelocityPass(const Params& params) : mParams(params) {}

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

private:
    Params mParams;
};

}  // namespace fp
