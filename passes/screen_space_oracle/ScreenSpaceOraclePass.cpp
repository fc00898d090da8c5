#include "passes/screen_space_oracle/ScreenSpaceOraclePass.h"

#include "framework/PassPorts.h"
#include "passes/screen_space_oracle/ScreenSpaceOracleKernel.h"
#include "screenspace/GBuffer.h"

namespace fp {

namespace {
using screen_space_oracle::kAo;
using screen_space_oracle::kAoWithinRadius;
using screen_space_oracle::kColor;
using screen_space_oracle::kDiffuse;
using screen_space_oracle::kHitFraction;
constexpr const char* kSpecularOut = screen_space_oracle::kSpecular;
}  // namespace

ParamSpec<ScreenSpaceOracleParams> ScreenSpaceOraclePass::paramSpec() {
    ParamSpec<ScreenSpaceOracleParams> s;
    s.add("rays", &Params::rays,
          "rays per pixel for each lobe (diffuse: cosine; specular: the pixel's GGX lobe, VNDF "
          "sampled); the noise falls as 1/√rays")
        .range(1, 65536);
    s.add("thickness", &Params::thickness,
          "cm: a sample at most this far behind a pixel's surface hits it; further behind, the ray "
          "passes behind the object")
        .range(0.0, 1e9);
    s.add("aoRadius", &Params::aoRadius,
          "metres: aoWithinRadius counts hits closer than this (capture --truth-ao-radius)")
        .range(0.0, 1e9);
    return s;
}

PassIO ScreenSpaceOraclePass::describe() const {
    PassIO io;
    // The error breakdown's oracle rung: which output estimates which truth layer.
    io.roles.raysParam = "rays";
    io.roles.oracleFor = {{"Truth.DiffuseIndirectOneBounce", kDiffuse},
                          {"Truth.DiffuseIndirectFull", kDiffuse},
                          {"Truth.AO", kAoWithinRadius},
                          {"Truth.AOAnyDistance", kAo}};
    io.inputs = {
        gbuffer::depthInput("full-resolution linear depth: what the rays march against"),
        gbuffer::normalInput(),
        gbuffer::shadingModelInput("unlit (0) and sky pixels are skipped"),
        gbuffer::baseColorInput("the specular lobe's F0 (with metallic and specular)"),
        gbuffer::metallicInput("the specular lobe's F0"),
        gbuffer::specularInput("the specular lobe's F0"),
        gbuffer::roughnessInput("the specular lobe's width"),
        {.name = kColor,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .captureDefault = "PrevSceneColor",
         .doc = "last frame's colour (what SSGI reads), read at the nearest pixel to where each "
                "hit pixel's surface was last frame; off last frame's screen it is 0"},
        gbuffer::velocityInput("optional per-pixel motion; camera reprojection when unbound"),
    };
    io.outputs = {
        {.name = kDiffuse,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "mean radiance of the cosine rays (irradiance/π, as ssgi.diffuse and "
                "Truth.DiffuseIndirectOneBounce); 0 on skipped pixels"},
        {.name = kSpecularOut,
         .channels = {"R", "G", "B"},
         .kind = PortKind::Color,
         .doc = "indirect specular radiance through the pixel's GGX lobe (F·D·Vis, as "
                "Truth.Specular); traced only when read"},
        {.name = kHitFraction, .channels = {"Y"}, .doc = "fraction of the cosine rays that hit"},
        {.name = kAo, .channels = {"Y"}, .doc = "1 − hitFraction: occluders at any distance on screen (as Truth.AOAnyDistance)"},
        {.name = kAoWithinRadius,
         .channels = {"Y"},
         .doc = "1 − the fraction of cosine rays that hit within aoRadius (as Truth.AO)"},
    };
    io.needsCamera = true;
    io.workUnit = "marchSteps";
    return io;
}

PassMemory ScreenSpaceOraclePass::memoryBytes(Extent frame) const {
    // Each pixel's tangent plane and its hit colour.
    return {(sizeof(screen_space_oracle::TangentPlane) + sizeof(Vec3f)) * std::size_t(frame.width) *
                std::size_t(frame.height),
            0};
}

void ScreenSpaceOraclePass::execute(PassContext& ctx) {
    screen_space_oracle::run(ctx, HostPorts{ctx}, CpuPixels{}, mParams.rays, mParams.thickness,
                             mParams.aoRadius);
}

}  // namespace fp
