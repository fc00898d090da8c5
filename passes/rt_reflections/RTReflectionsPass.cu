// RTReflectionsPass on the GPU: rtr::run through framepass's BVH in device memory, the scene's
// lights and the sky light's cubemap copied with the frame, one thread per traced texel.
#include "foundation/CudaLaunch.cuh"
#include "framework/PassPorts.h"
#include "passes/rt_reflections/RTReflectionsKernel.h"
#include "passes/rt_reflections/RTReflectionsPass.h"

namespace fp {

void RTReflectionsPass::executeCuda(PassContext& ctx) {
    const DevicePorts ports{ctx};
    const rtr::FrameSetup setup = frameSetup(ctx);
    const DirectLighting lighting(ctx.scene(), setup.lightSamples);
    std::shared_ptr<const LightView> lights;
    const BvhTracer tracer = bvhTracerFor(ports, lighting, lights);
    std::shared_ptr<const Vec3f> cubeTexels;
    const rtr::Sky sky = rtr::skyFor(ports, mSky.get(), cubeTexels);
    // A warp traces 8×4 neighbouring texels' rays (CudaLaunch.cuh's PixelBlock), as rt_shadows.
    rtr::run(ctx, ports, CudaPixels{cuda::PixelBlock::Squares}, setup, sky,
             outputExtents(rtr::kReflection, ctx.frame().extent).front(), tracer, mParams.hybrid,
             "rt_reflections");
}

}  // namespace fp
