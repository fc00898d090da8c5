#include "passes/hybrid_reflections/HybridReflectionsPass.h"

#include "framework/PassPorts.h"
#include "foundation/Error.h"
#include "foundation/PerPixel.h"
#include "passes/hybrid_reflections/HybridReflectionsKernel.h"
#include "passes/ssr/SSRKernel.h"
#include "shading/DirectLighting.h"
#include "shading/RayOriginBias.h"

#include <bit>
#include <limits>

namespace fp {

namespace {

constexpr uint32_t kSeed = 0x48524546u;  // "HREF"

}  // namespace

ParamSpec<HybridReflectionsParams> HybridReflectionsPass::paramSpec() {
    ParamSpec<HybridReflectionsParams> s = SSRPass::paramSpecOf<HybridReflectionsParams>();
    s.add("normalBias", &Params::normalBias, "a fallback ray's origin bias, cm, as rt_reflections'")
        .range(0.01, 1e6)
        .cvar("r.RayTracing.Reflections.NormalBias");
    s.add("shadows", &Params::shadows,
          "0: a fallback hit's lights unshadowed; otherwise one shadow ray a light, as "
          "rt_reflections' hard shadows")
        .range(0, 2)
        .cvar("r.RayTracing.Reflections.Shadows");
    s.add("hitIndirectBounces", &Params::hitIndirectBounces,
          "a fallback hit's diffuse indirect light, as rt_reflections': 0 the sky light's SH, "
          "n > 0 traced by one cosine path of n bounces")
        .range(0, 16);
    s.add("traversal", &Params::traversal,
          "the fallback rays' \"embree\": Embree's scene; \"bvh\": framepass's own BVH, the "
          "code the GPU runs (on the GPU the pass always traverses it; hitIndirectBounces > 0 "
          "keeps the pass on the CPU, and \"bvh\" is refused there under a sky light)")
        .choices({"embree", "bvh"});
    return s;
}

PassIO HybridReflectionsPass::describe() const {
    // SSR's ports, all of them: its rays are SSR's.
    PassIO io = SSRPass(mParams).describe();
    io.roles.framepassOwn = true;
    io.roles.tracesRays = true;  // bench replays its fallback rays in bare Embree loops
    io.needsScene = true;
    return io;
}

PassMemory HybridReflectionsPass::memoryBytes(Extent frame) const {
    return SSRPass(mParams).memoryBytes(frame);  // SSR's rays and SSR's history
}

hybrid_reflections::SceneFallback<BvhTracer> HybridReflectionsPass::bvhFallback(
    PassContext& ctx, const BvhTracer& tracer, const rtr::Sky& sky, unsigned long long* counts) {
    const RayScene& rs = ctx.scene();
    return {tracer,
            sky,
            mParams.shadows != 0,
            1,
            mParams.hitIndirectBounces,
            ctx.frame().camera.current.position - rs.origin(),
            RayBias::fromCm(mParams.normalBias, float(rs.scene().centimetre())),
            Rng::frameKey(ctx.frame().number, kSeed),
            counts};
}

void HybridReflectionsPass::addFallbackWork(PassContext& ctx, const unsigned long long* counts) const {
    using namespace hybrid_reflections;
    ctx.addWork("fallbackRays", counts[kFallbackRays]);
    ctx.addWork("fallbackHits", counts[kFallbackHits]);
    ctx.addWork("skyRays", counts[kSkyRays]);
    ctx.addWork("shadowRays", counts[kShadowRays]);
    if (mParams.hitIndirectBounces > 0) ctx.addWork("indirectRays", counts[kIndirectRays]);
}

void HybridReflectionsPass::execute(PassContext& ctx) {
    using namespace hybrid_reflections;
    const RayScene& rs = ctx.scene();
    mSky = ReflectedSky::of(rs.scene().environment.sky, mSky);
    const DirectLighting lighting(rs, 1);
    std::shared_ptr<const Vec3f> cubeTexels;
    const rtr::Sky sky = rtr::skyFor(HostPorts{ctx}, mSky.get(), cubeTexels);
    unsigned long long counts[kFallbackCounters] = {};
    std::shared_ptr<const LightView> lights;
    SceneFallback<BvhTracer> bvh =
        bvhFallback(ctx, bvhTracerFor(HostPorts{ctx}, lighting, lights), sky, counts);
    if (mParams.traversal == "bvh") {
        if (mSky && mParams.hitIndirectBounces > 0)
            throw UsageError("hybrid_reflections: traversal \"bvh\" reads no sky along a hit's "
                             "indirect path, and hitIndirectBounces asks for one under the scene's "
                             "sky light: use traversal \"embree\"");
        hybrid_reflections::runSsr(ctx, HostPorts{ctx}, CpuPixels{}, mParams, bvh);
    } else {
        DiffusePathSetup paths;
        paths.scene = &rs;
        paths.lighting = &lighting;
        paths.sky = mSky ? mSky->source : nullptr;
        const SceneFallback<EmbreeTracer> embree{EmbreeTracer{paths}, bvh.sky, bvh.shadowed,
                                                 bvh.lightSamples, bvh.indirectBounces,
                                                 bvh.eyeOffset, bvh.bias, bvh.rngKey, counts};
        hybrid_reflections::runSsr(ctx, HostPorts{ctx}, CpuPixels{}, mParams, embree);
    }
    addFallbackWork(ctx, counts);
}

}  // namespace fp
