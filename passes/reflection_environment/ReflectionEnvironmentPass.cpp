#include "passes/reflection_environment/ReflectionEnvironmentPass.h"

#include "foundation/Environment.h"
#include "framework/PassPorts.h"
#include "screenspace/GBuffer.h"

namespace fp {

namespace {
using reflection_environment::kAo;
using reflection_environment::kColor;
using reflection_environment::kDiffuse;
using reflection_environment::kReflection;
using reflection_environment::kSpecular;
}  // namespace

ParamSpec<ReflectionEnvironmentParams> ReflectionEnvironmentPass::paramSpec() {
    ParamSpec<ReflectionEnvironmentParams> s;
    s.add("reflections", &Params::reflections,
          "the specular half: screen-space reflections, then the reflection captures and the "
          "sky's prefiltered radiance, × EnvBRDF")
        .cvar("r.ReflectionEnvironment");
    s.add("skyDiffuse", &Params::skyDiffuse, "the sky light's diffuse (SH3 irradiance × DiffuseColor)");
    s.add("specularOcclusion", &Params::specularOcclusion,
          "Lagarde's specular occlusion from GBuffer AO × screen-space AO on what the reflections "
          "leave to the sky");
    return s;
}

PassIO ReflectionEnvironmentPass::describe() const {
    PassIO io;
    io.inputs = {
        gbuffer::sceneColorInput(kColor, "the lit colour the reflections and sky light add to"),
        gbuffer::depthInput("linear view depth (position and view direction)"),
        gbuffer::normalInput(),
        gbuffer::baseColorInput(),
        gbuffer::metallicInput("metalness (F0 and DiffuseColor)"),
        gbuffer::specularInput("dielectric specular (F0 = 0.08 × specular)"),
        gbuffer::roughnessInput("roughness: EnvBRDF, the sky's mip, the off-specular peak"),
        gbuffer::shadingModelInput("shading model id (unlit untouched, hair without reflections)"),
        gbuffer::customDataInput("subsurface / fuzz colour (√) and clear coat, roughness", true),
        gbuffer::gbufferAOInput(true),
        {.name = kReflection,
         .channels = {"R", "G", "B", "A"},
         .kind = PortKind::Color,
         .optional = true,
         .doc = "screen-space reflections: premultiplied radiance, A = coverage (none: 0)"},
        {.name = kAo,
         .channels = {"Y"},
         .optional = true,
         .doc = "screen-space AO (SSGI's), full or half resolution (none: 1)"},
    };
    io.outputs = {
        {.name = kColor, .channels = {"R", "G", "B"}, .kind = PortKind::Color,
         .doc = "the colour with the sky light's diffuse and the reflections added"},
        {.name = kSpecular, .channels = {"R", "G", "B"}, .kind = PortKind::Color,
         .doc = "the reflected specular that was added (SSR, sky, × EnvBRDF)"},
        {.name = kDiffuse, .channels = {"R", "G", "B"}, .kind = PortKind::Color,
         .doc = "the sky light's diffuse that was added"},
    };
    io.needsCamera = true;
    io.needsEnvironment = true;
    return io;
}

float ReflectionEnvironmentPass::specularOcclusion(float NoV, float ao, float roughness) {
    return reflection_environment::specularOcclusion(NoV, ao, roughness);
}

const ReflectionEnvironmentPass::SkyLighting& ReflectionEnvironmentPass::skyLighting(const SkyLight& sky) {
    if (!mSky || mSky->source != &sky) {
        auto s = std::make_shared<SkyLighting>();
        s->source = &sky;
        s->cube = Cubemap::render(Cubemap::kSkyLightSize, [&](const Vec3f& d) { return sky.radiance(d); });
        s->sh = s->cube.projectSH();
        mSky = std::move(s);
    }
    return *mSky;
}

const std::vector<Cubemap>& ReflectionEnvironmentPass::captureCubes(const Environment& env) {
    if (mCubesOf != &env || mCaptureCubes.size() != env.captures.size()) {
        mCaptureCubes.clear();
        for (const ReflectionCapture& c : env.captures) mCaptureCubes.push_back(Cubemap::fromFaces(c.faces));
        mCubesOf = &env;
    }
    return mCaptureCubes;
}

reflection_environment::Lighting ReflectionEnvironmentPass::lighting(PassContext& ctx) {
    const Environment& env = ctx.environment();
    reflection_environment::Lighting l;
    l.reflections = mParams.reflections;
    l.skyDiffuse = mParams.skyDiffuse;
    l.specularOcclusion = mParams.specularOcclusion;
    if (env.sky.enabled) {
        const SkyLighting& sky = skyLighting(env.sky);
        l.skyCube = &sky.cube;
        l.skySh = sky.sh;
        l.occlusionTint = env.sky.occlusionTint;
    }
    // The captures relative to this frame's eye, in the environment's (ascending radius) order.
    if (mParams.reflections && !env.captures.empty()) {
        const Vec3d eye = ctx.frame().camera.current.position;
        const std::vector<Cubemap>& cubes = captureCubes(env);
        for (std::size_t i = 0; i < env.captures.size(); ++i) {
            const ReflectionCapture& c = env.captures[i];
            PreparedCapture p;
            p.box = c.shape == ReflectionCapture::Shape::Box;
            p.centre = Vec3f(c.position - eye);
            p.radius = float(c.radius);
            p.extent = Vec3f(c.extent);
            p.transition = float(c.transitionDistance);
            p.brightness = c.brightness;
            p.offset = Vec3f(c.offset);
            p.cube = cubes[i].view();
            l.captures.push_back(p);
            l.captureCubes.push_back(&cubes[i]);
        }
    }
    return l;
}

void ReflectionEnvironmentPass::execute(PassContext& ctx) {
    reflection_environment::run(ctx, HostPorts{ctx}, CpuPixels{}, lighting(ctx));
}

}  // namespace fp
