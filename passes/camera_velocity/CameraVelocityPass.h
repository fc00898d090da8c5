#pragma once
// Camera motion vectors: where each pixel's surface was on last frame's screen when only the
// camera moved (Unreal's velocity pass writes these for static geometry; moving objects add their
// own motion). For captures without a Velocity buffer, so the reduction and the SSGI denoiser can
// reproject through motion vectors as they do with Unreal's.
#include "framework/Params.h"
#include "framework/Pass.h"

namespace fp {

struct CameraVelocityParams {
    float skyDistance =
        0.0f;  //!< depths at or beyond this move as sky (rotation only); 0 = +inf only
};

class CameraVelocityPass final : public PassWithParams<CameraVelocityParams> {
public:
    static ParamSpec<Params> paramSpec();
    using PassWithParams::PassWithParams;

    PassIO describe() const override;
    void execute(PassContext& ctx) override;

    FP_PASS_HAS_CUDA_KERNEL  // CameraVelocityPass.cu
};

}  // namespace fp
