#include "passes/ssgi/SSGIPass.h"

#include "screenspace/GBuffer.h"
#include "framework/PassPorts.h"
#include "foundation/PerPixel.h"
#include "passes/ssgi/SSGIKernel.h"
#include "passes/ssgi/SSGILanes.h"

#include <algorithm>

namespace fp {

ParamSpec<SSGIParams> SSGIPass::paramSpec() {
    ParamSpec<SSGIParams> s;
    s.add("quality", &Params::quality,
          "1..4 → 4/8/16/32 rays per pixel and 8/8/8/12 steps per ray (algorithms §4.2)")
        .range(1, 4)
        .cvar("r.SSGI.Quality");
    s.add("rays", &Params::rays,
          "rays per pixel in place of the quality's count, with the quality's steps (0: the "
          "quality's 4/8/16/32). Not an Unreal setting: many rays converge the pass to what its "
          "algorithm gives without noise (bench's error decomposition uses it)")
        .range(0, kMaxRays);
    s.add("halfRes", &Params::halfRes,
          "trace at half resolution (the top-left pixel of every 2×2 block); UE5 names the cvar "
          "r.DiffuseIndirect.HalfRes (default 1)")
        .cvar("r.SSGI.HalfRes")
        .cvar("r.DiffuseIndirect.HalfRes");
    s.add("indirectLightingColorScale", &Params::indirectLightingColorScale,
          "4.27 only: post-process IndirectLightingIntensity (× white IndirectLightingColor)")
        .range(0.0, 1e6);
    s.add("lanes", &Params::lanes,
          "CPU only: trace a pixel's rays a SIMD vector at a time (the widest instruction set the "
          "CPU has); false runs the scalar reference one ray at a time. Both give the same bits");
    return s;
}

SSGIQuality SSGIPass::qualityTable(int quality) {
    static constexpr SSGIQuality kTable[] = {{4, 8}, {8, 8}, {16, 8}, {32, 12}};
    return kTable[std::clamp(quality, 1, 4) - 1];
}

SSGIQuality SSGIPass::traced(int quality, int rays) {
    SSGIQuality q = qualityTable(quality);
    if (rays > 0)
        q.rays = rays;
    return q;
}

Extent SSGIPass::traceExtent(Extent frame, bool halfRes) {
    return fp::traceExtent(frame, halfRes);
}

PassIO SSGIPass::describe() const {
    PassIO io;
    io.roles.unrealSwitch = "r.SSGI.Enable=1";  // 4.27 (UE5: r.DynamicGlobalIlluminationMethod=2)
    io.roles.raysParam = "rays";  // the error breakdown's converged rung raises it
    io.inputs = {
        gbuffer::depthInput(),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit (0) pixels are skipped"),
        {.name = ssgi::kFurthestHzb, .channels = {"Z"}, .doc = "furthest HZB (device Z)"},
        {.name = ssgi::kReducedColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "last frame's colour, reprojected and reduced to 5 mips"},
    };
    io.outputs = {
        {.name = ssgi::kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "mean incoming radiance of the rays (irradiance/π); 0 on skipped pixels"},
        {.name = ssgi::kAo,
         .channels = {"Y"},
         .doc = "1 − fraction of rays that hit; 1 on skipped pixels"},
        {.name = ssgi::kHitMask,
         .channels = {"Y"},
         .doc = "debug: fraction of rays that hit (0 on skipped pixels)"},
        {.name = ssgi::kHitDistance,
         .channels = {"Y"},
         .doc = "debug: mean distance from the pixel to its rays' hits, scene units (0: no hit)"},
    };
    io.needsCamera = true;
    io.workUnit = "hzbSamples";
    return io;
}

std::vector<Extent> SSGIPass::outputExtents(std::string_view, Extent frame) const {
    return {traceExtent(frame, mParams.halfRes)};
}

Vec3f SSGIPass::rayDirection(const Vec3f& n,
                             int x,
                             int y,
                             uint32_t frameMod8,
                             int index,
                             int count) {
    return ssgi::rayDirection<float>(ssgi::rayBasis(n, x, y, frameMod8), uint32_t(index), count);
}

void SSGIPass::execute(PassContext& ctx) {
    const SSGIQuality q = traced(mParams.quality, mParams.rays);
    if (!mParams.lanes) {
        ssgi::run(ctx, HostPorts{ctx}, CpuPixels{}, q.rays, q.steps, mParams.halfRes,
                  mParams.indirectLightingColorScale);
        return;
    }
    const ssgi::Frame f = ssgi::bindFrame(HostPorts{ctx}, ctx.frame(), q.rays, q.steps,
                                          mParams.halfRes, mParams.indirectLightingColorScale);
    ssgi::reportWork(ctx, ssgi::traceInLanes(f));
}

}  // namespace fp
