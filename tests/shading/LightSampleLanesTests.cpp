// A wave of reflection hits' light samples in SIMD lanes (shading/ReflectionHitLanes.h) against
// the scalar path's own (drawLightRays, as shadeLights draws them), hit by hit, bit for bit, on
// every instruction set this CPU runs: every kind of light, one sample a light and several (a
// square count, stratified, and one that is not), lights behind a hit or outside a spot's cone
// beside lights that reach it, and a wave that leaves a partial vector.
#include "screenspace/Lanes.h"
#include "shading/ReflectionHitLanes.h"

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace fp {

namespace {

struct Lights {
    std::vector<LightView> views;
    int lightCount() const { return int(views.size()); }
    const LightView& lightView(int i) const { return views[std::size_t(i)]; }
};

Vec3f randomUnit(std::mt19937& gen) {
    std::normal_distribution<float> g;
    return normalize(Vec3f{g(gen), g(gen), g(gen)});
}

bool sameBits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

}  // namespace

TEST_CASE("light samples in SIMD lanes give the scalar path's samples, bit for bit") {
    std::vector<Light> lights(5);
    lights[0].type = LightType::Directional;
    lights[0].direction = {0.3, -1, 0.2};
    lights[0].sourceAngleDegrees = 2.0f;
    lights[1].type = LightType::Spot;
    lights[1].position = {1, 4, -1};
    lights[1].direction = {0, -1, 0.3};
    lights[1].innerConeDegrees = 10.0f;
    lights[1].outerConeDegrees = 30.0f;
    lights[1].radius = 0.2f;
    lights[1].intensity = 80.0f;
    lights[2].type = LightType::Point;
    lights[2].position = {-2, 3, 1};
    lights[2].radius = 0.3f;
    lights[2].intensity = 40.0f;
    lights[3].type = LightType::Rect;
    lights[3].position = {0, 2.5, 0};
    lights[3].halfU = {0.5, 0, 0};
    lights[3].halfV = {0, 0, 0.5};
    lights[3].intensity = 5.0f;
    lights[4].type = LightType::Point;  // punctual: one sample at its centre
    lights[4].position = {2, 1, 2};
    lights[4].intensity = 20.0f;
    Lights scalar;
    for (const Light& l : lights) scalar.views.push_back(LightView::of(l, {}));

    std::mt19937 gen(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const int n = 37;  // two vectors of 16 and a partial one
    std::vector<SurfacePoint> hits(static_cast<std::size_t>(n));
    for (SurfacePoint& s : hits) {
        s.position = {4 * unit(gen) - 2, 2 * unit(gen), 4 * unit(gen) - 2};
        s.normal = randomUnit(gen);
        s.geometricNormal = s.normal;
        s.toViewer = normalize(s.normal + randomUnit(gen) * 0.9f);
        const float roughness = unit(gen) < 0.2f ? 0.0f : unit(gen);  // below the lights' floor too
        s.brdf = SurfaceBRDF::fromMaterial({unit(gen), unit(gen), unit(gen)}, unit(gen), unit(gen),
                                           roughness);
    }
    const std::vector<int64_t> targets = laneTargetsHere();
    REQUIRE(!targets.empty());
    for (int samples : {1, 3, 4}) {
        CAPTURE(samples);
        int slots = 0;
        for (const LightView& v : scalar.views) slots += samplesOf(v, samples);
        for (int64_t target : targets) {
            INFO("target ", target);
            ReflectionHitLanes lanes;
            lanes.resize(n);
            for (int i = 0; i < n; ++i)
                lanes.set(std::size_t(i), hits[std::size_t(i)], Rng::fromKey(11, i, 3).state());
            SampleLanes out;
            useOnlyLaneTarget(target);
            drawLightRayLanes(scalar.views.data(), scalar.lightCount(), samples, lanes, out);
            useOnlyLaneTarget(0);
            int kept = 0, dropped = 0, differs = 0;
            for (int i = 0; i < n; ++i) {
                const SurfacePoint& s = hits[std::size_t(i)];
                Rng rng = Rng::fromKey(11, i, 3);
                // The scalar path's samples that reach s from above, in order.
                std::vector<LightSample> drawn;
                std::vector<Vec3f> values;
                drawLightRays(
                    scalar, samples, s, rng,
                    [&](const LightSample& ls, float NoL) {
                        drawn.push_back(ls);
                        values.push_back(lightValue(s, ls, NoL));
                    },
                    [](int) {});
                // The lanes' kept samples in slot order are those, one for one.
                std::size_t next = 0;
                for (int slot = 0; slot < slots; ++slot) {
                    const std::size_t at = std::size_t(slot) * std::size_t(out.stride) + std::size_t(i);
                    if (!out.keep[at]) {
                        ++dropped;
                        continue;
                    }
                    ++kept;
                    if (next >= drawn.size()) {
                        ++differs;
                        continue;
                    }
                    const LightSample& ls = drawn[next];
                    const Vec3f& v = values[next];
                    ++next;
                    differs += !(sameBits(out.dx[at], ls.shadowDir.x) && sameBits(out.dy[at], ls.shadowDir.y) &&
                                 sameBits(out.dz[at], ls.shadowDir.z) &&
                                 sameBits(out.tfar[at], ls.shadowDistance) && sameBits(out.lr[at], v.x) &&
                                 sameBits(out.lg[at], v.y) && sameBits(out.lb[at], v.z));
                }
                CHECK(next == drawn.size());  // the lanes kept every sample the scalar path kept
                CHECK(lanes.rng[std::size_t(i)] == rng.state());  // and drew as many numbers
            }
            CHECK(differs == 0);
            // Not vacuous: samples kept and samples dropped (behind a hit, outside the cone).
            CHECK(kept > n);
            CHECK(dropped > n / 2);
        }
    }
}

}  // namespace fp
