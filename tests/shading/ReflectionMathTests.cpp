// The reflection environment's building blocks: the EnvBRDF table and its analytic fit, order-3
// spherical harmonics, the prefiltered cubemap, the sky light's lat-long lookup and the
// reflection captures' parallax, fade and compositing.
#include "foundation/Environment.h"
#include "foundation/Sampling.h"
#include "shading/Cubemap.h"
#include "shading/EnvBRDF.h"
#include "shading/ReflectionCaptures.h"
#include "shading/SphericalHarmonics.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

namespace fp {

namespace {

// The split-sum terms by a product rule in (θ_H, φ_H) that is independent of the table's
// Hammersley set: the GGX half-vector CDF's midpoints × uniform φ, in double. Each cell carries
// equal probability, so this is a stratified (not random) importance-sampled quadrature.
EnvBRDFTerms quadrature(double NoV, double roughness, int cells) {
    const double m = roughness * roughness, a2 = m * m;
    const double Vx = std::sqrt(1.0 - NoV * NoV);
    double A = 0, B = 0;
    for (int j = 0; j < cells; ++j) {
        const double e2 = (j + 0.5) / cells;
        const double cosT = std::sqrt((1.0 - e2) / (1.0 + (a2 - 1.0) * e2));
        const double sinT = std::sqrt(1.0 - cosT * cosT);
        for (int i = 0; i < cells; ++i) {
            const double phi = 2.0 * kPi * (i + 0.5) / cells;
            const double VoH = Vx * sinT * std::cos(phi) + NoV * cosT;
            const double NoL = 2.0 * VoH * cosT - NoV;
            if (NoL <= 0.0) continue;
            const double vis = 0.5 / (NoL * (NoV * (1 - m) + m) + NoV * (NoL * (1 - m) + m));
            const double w = NoL * vis * 4.0 * VoH / cosT;
            const double fc = std::pow(1.0 - VoH, 5.0);
            A += w * (1 - fc);
            B += w * fc;
        }
    }
    const double n = double(cells) * cells;
    return {float(A / n), float(B / n)};
}

}  // namespace

TEST_CASE("EnvBRDF table: near a mirror the terms are Schlick's Fresnel split in two") {
    // The first roughness row (r = 1/64, α = 2.4·10⁻⁴) is a mirror up to terms in α/NoV: the
    // sampled half vectors stay within ~α of N, and the visibility's m-terms are relative O(m/NoV).
    // From NoV ≥ 1/16, m/NoV ≤ 0.004; 16-bit storage adds 8·10⁻⁶.
    const EnvBRDFLut& lut = EnvBRDFLut::instance();
    for (int i = 8; i < EnvBRDFLut::kNoVTexels; i += 17) {
        const float NoV = (i + 0.5f) / EnvBRDFLut::kNoVTexels;
        const float fresnel = std::pow(1.0f - NoV, 5.0f);
        CAPTURE(NoV);
        CHECK(std::abs(lut.texel(i, 0).a - (1.0f - fresnel)) <= 5e-3f);
        CHECK(std::abs(lut.texel(i, 0).b - fresnel) <= 5e-3f);
    }
}

TEST_CASE("EnvBRDF table: stored as generated, read bilinearly on texel centres") {
    const EnvBRDFLut& lut = EnvBRDFLut::instance();
    const float halfStep = 0.5f / 65535.0f + 1e-7f;  // 16-bit unorm rounding
    for (int j : {0, 7, 31})
        for (int i : {0, 63, 127}) {
            const float NoV = (i + 0.5f) / 128.0f, r = (j + 0.5f) / 32.0f;
            const EnvBRDFTerms direct = integrateEnvBRDF(NoV, r, EnvBRDFLut::kSamples);
            CHECK(std::abs(lut.texel(i, j).a - std::clamp(direct.a, 0.0f, 1.0f)) <= halfStep);
            CHECK(std::abs(lut.texel(i, j).b - std::clamp(direct.b, 0.0f, 1.0f)) <= halfStep);
            // A lookup at the texel's centre is the texel.
            CHECK(lut.lookup(NoV, r).a == doctest::Approx(lut.texel(i, j).a).epsilon(1e-6));
        }
    // Halfway between two centres: the mean of the two texels.
    const EnvBRDFTerms mid = lut.lookup(11.0f / 128.0f, 4.5f / 32.0f);
    CHECK(mid.a == doctest::Approx(0.5f * (lut.texel(10, 4).a + lut.texel(11, 4).a)).epsilon(1e-5));
    // Beyond the outer centres the edge texel holds (clamp addressing), NaN reads the first.
    CHECK(lut.lookup(1.0f, 1.0f).a == lut.texel(127, 31).a);
    CHECK(lut.lookup(std::nanf(""), 0.0f).a == lut.texel(0, 0).a);
}

TEST_CASE("EnvBRDF table against a direct numerical integration") {
    // The table integrates with Unreal's 128 Hammersley points; the reference is a 512² stratified
    // product rule (its own error is far below 10⁻³). By Koksma–Hlawka the 128-point rule's error
    // is at most the integrand's variation (≤ 1: after importance sampling the weight is
    // 4·Vis·NoL·VoH/NoH ≤ 1 up to the Fresnel split) × the 2-D Hammersley discrepancy, about
    // log2(128)/128 = 0.055.
    const EnvBRDFLut& lut = EnvBRDFLut::instance();
    for (int j : {3, 10, 20, 31})
        for (int i : {5, 40, 90, 127}) {
            const double NoV = (i + 0.5) / 128.0, r = (j + 0.5) / 32.0;
            const EnvBRDFTerms ref = quadrature(NoV, r, 512);
            CAPTURE(NoV);
            CAPTURE(r);
            CHECK(std::abs(lut.texel(i, j).a - ref.a) <= 0.055f);
            CHECK(std::abs(lut.texel(i, j).b - ref.b) <= 0.055f);
            // Energy: with F = 1 the lobe reflects at most what arrives.
            CHECK(ref.a + ref.b <= 1.0f + 1e-3f);
        }
}

TEST_CASE("EnvBRDFApprox at hand-worked values") {
    // r = 0, NoV = 1: a004 = min(1, 2^−9.28)·1 + 0.0425 = 0.0441100;
    //   A = −1.04·a004 + 1.04 = 0.994126, B = 1.04·a004 − 0.04 = 0.005874.
    const EnvBRDFTerms smooth = envBRDFApprox(1.0f, 0.0f);
    CHECK(smooth.a == doctest::Approx(0.994126).epsilon(2e-6));
    CHECK(smooth.b == doctest::Approx(0.005874).epsilon(2e-4));
    // r = 1: r = (0, 0.015, 0.468, −0.018), a004 = 0.015 for any NoV: A = 0.4524, B = −0.0024.
    const EnvBRDFTerms rough = envBRDFApprox(0.5f, 1.0f);
    CHECK(rough.a == doctest::Approx(0.4524).epsilon(1e-5));
    CHECK(rough.b == doctest::Approx(-0.0024).epsilon(1e-3));
    // F0 below 2 %: the bias term is cut (saturate(50·F0.g)).
    CHECK(applyEnvBRDF({0.01f, 0.01f, 0.01f}, {0.5f, 0.2f}).x == doctest::Approx(0.005f + 0.1f));
    CHECK(applyEnvBRDF({0.04f, 0.04f, 0.04f}, {0.5f, 0.2f}).x == doctest::Approx(0.02f + 0.2f));
}

TEST_CASE("SH3: a constant sky and a single direction reconstruct") {
    // A constant radiance L projects to L₀₀ = L·√(4π) alone; both the radiance and irradiance/π
    // reconstruct L exactly (float rounding of the cube's 98 304 solid angles, ≲ 10⁻⁵).
    const Vec3f L{1.0f, 2.0f, 3.0f};
    const Cubemap sky = Cubemap::render(32, [&](const Vec3f&) { return L; });
    const SH3 sh = sky.projectSH();
    for (const Vec3f& n : {Vec3f{0, 1, 0}, normalize(Vec3f{1, -2, 0.5f}), Vec3f{0, 0, -1}}) {
        CHECK(sh.diffuse(n).x == doctest::Approx(1.0).epsilon(1e-5));
        CHECK(sh.diffuse(n).z == doctest::Approx(3.0).epsilon(1e-5));
        CHECK(sh.radiance(n).y == doctest::Approx(2.0).epsilon(1e-5));
    }
    // A single direction d of power P: L_lm = P·Y_lm(d). By the addition theorem
    // Σ_m Y_lm(d)² = (2l + 1)/(4π), so the band-limited radiance at d is 9P/(4π), and
    // irradiance/π there is P·(1 + 3·2/3 + 5·1/4)/(4π) = 4.25P/(4π) — 1.0625 × the exact P/π,
    // the known overshoot of order-3 irradiance for a point source.
    SH3 point;
    const Vec3f d = normalize(Vec3f{0.3f, 0.8f, -0.52f});
    point.add(d, {1, 1, 1}, 1.0f);
    CHECK(point.radiance(d).x == doctest::Approx(9.0 / (4.0 * kPi)).epsilon(1e-6));
    CHECK(point.diffuse(d).x == doctest::Approx(4.25 / (4.0 * kPi)).epsilon(1e-6));
    CHECK(point.diffuse(d).x == doctest::Approx(1.0625 / kPi).epsilon(1e-6));
    // Away from d, at cos γ = c the sum is P·(1 + 2c + (5/4)·(3c² − 1)/2)/(4π): 0.25P/(4π) at
    // c = −1 (the order-3 lobe's back), negative around c = −8/15 (−0.158P/(4π)), which Unreal
    // clamps to 0.
    CHECK(point.diffuse(-d).x == doctest::Approx(0.25 / (4.0 * kPi)).epsilon(1e-5));
    Vec3f t, b;
    orthonormalBasis(d, t, b);
    const float c = -8.0f / 15.0f;
    CHECK(point.diffuse(d * c + t * std::sqrt(1.0f - c * c)).x == 0.0f);
}

TEST_CASE("Cubemap: solid angles, roughness mips, prefiltering keeps a constant and the mean") {
    double total = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) total += 6.0 * Cubemap::texelSolidAngle(x, y, 16);
    CHECK(total == doctest::Approx(4.0 * kPi).epsilon(1e-12));

    const Cubemap constant = Cubemap::render(128, [](const Vec3f&) { return Vec3f{0.5f, 1.0f, 2.0f}; });
    CHECK(constant.mipCount() == 8);
    // Unreal's mapping for a 128² capture: mip = 6 − (1 − 1.2·log2 r): r = 1 → 5, r = 0.5 → 3.8.
    CHECK(constant.mipForRoughness(1.0f) == doctest::Approx(5.0f));
    CHECK(constant.mipForRoughness(0.5f) == doctest::Approx(3.8f));
    CHECK(constant.roughnessForMip(5) == doctest::Approx(1.0f));
    CHECK(constant.roughnessForMip(0) == doctest::Approx(std::exp2(-5.0 / 1.2)).epsilon(1e-6));
    for (float mip : {0.0f, 2.5f, 5.0f, 7.0f})
        CHECK(constant.sample(normalize(Vec3f{0.2f, -0.7f, 0.4f}), mip).z == doctest::Approx(2.0f).epsilon(1e-5));

    // A rotation-invariant kernel normalised per direction preserves the sphere's mean: ∫∫K f =
    // ∫ f. Texel quadrature of a smooth sky (a gradient from 0 below to 2 above) keeps it to the
    // discretisation of the coarse mips, well under 2 %.
    const Cubemap gradient = Cubemap::render(64, [](const Vec3f& d) { return Vec3f{1.0f + d.y, 1.0f, 1.0f}; });
    const auto meanAt = [&](float mip) {
        double sum = 0, weight = 0;
        for (int f = 0; f < 6; ++f)
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) {
                    const double w = Cubemap::texelSolidAngle(x, y, 32);
                    sum += w * gradient.sample(Cubemap::direction(f, (2 * x + 1) / 32.0f - 1, (2 * y + 1) / 32.0f - 1), mip).x;
                    weight += w;
                }
        return sum / weight;
    };
    CHECK(meanAt(0) == doctest::Approx(1.0).epsilon(1e-3));
    CHECK(meanAt(4) == doctest::Approx(1.0).epsilon(2e-2));
    // Rough mips blur the gradient towards its mean: the zenith darkens from 2.
    const float zenith0 = gradient.sample({0, 1, 0}, 0).x, zenith4 = gradient.sample({0, 1, 0}, 4).x;
    CHECK(zenith0 == doctest::Approx(2.0f).epsilon(2e-3));
    CHECK(zenith4 < zenith0 - 0.1f);
    CHECK(zenith4 > 1.0f);
}

TEST_CASE("Sky light: lat-long coordinates follow Blender's equirectangular map") {
    float u, v;
    // Y up: the zenith is row 0, the horizon the middle row, −X the middle column.
    SkyLight::latLongCoordinates({0, 1, 0}, LatLongUp::Y, u, v);
    CHECK(v == doctest::Approx(0.0f));
    SkyLight::latLongCoordinates({-1, 0, 0}, LatLongUp::Y, u, v);
    CHECK(u == doctest::Approx(0.5f));
    CHECK(v == doctest::Approx(0.5f));
    // Blender's +Y (here −Z with Y up, +Y with Z up) is u = 0.75.
    SkyLight::latLongCoordinates({0, 0, -1}, LatLongUp::Y, u, v);
    CHECK(u == doctest::Approx(0.75f));
    SkyLight::latLongCoordinates({0, 1, 0}, LatLongUp::Z, u, v);
    CHECK(u == doctest::Approx(0.75f));
    SkyLight::latLongCoordinates({0, 0, -1}, LatLongUp::Z, u, v);
    CHECK(v == doctest::Approx(1.0f));

    // A 4×2 map: top row red, bottom row blue; radiance is tinted by colour × intensity.
    SkyLight sky;
    sky.enabled = true;
    sky.color = {1, 1, 1};
    sky.intensity = 2.0f;
    sky.latLong = Image(4, 2, {"R", "G", "B"});
    for (int x = 0; x < 4; ++x) {
        sky.latLong.plane(0).at(x, 0) = 1.0f;
        sky.latLong.plane(2).at(x, 1) = 1.0f;
    }
    CHECK(sky.radiance({0, 1, 0}).x == doctest::Approx(2.0f));
    CHECK(sky.radiance({0, -1, 0}).z == doctest::Approx(2.0f));
    CHECK(sky.radiance({1, 0, 0}).x == doctest::Approx(1.0f));  // the horizon: halfway
    sky.enabled = false;
    CHECK(sky.radiance({0, 1, 0}).x == 0.0f);
}

}  // namespace fp

namespace fp {

TEST_CASE("Reflection captures: sphere parallax and its fade, by hand") {
    // p = (3, 0, 0) in a sphere of radius 10, reflecting up: b = 0, c = 9 − 100, t = √91.
    const CaptureLookup a = sphereParallax({3, 0, 0}, {0, 1, 0}, 10.0f, {});
    REQUIRE(a.inside);
    CHECK(a.direction.x == doctest::Approx(3.0f));
    CHECK(a.direction.y == doctest::Approx(std::sqrt(91.0f)));
    CHECK(length(a.direction) == doctest::Approx(10.0f));
    CHECK(a.distanceAlpha == 1.0f);  // within 60 % of the radius
    // The capture offset is taken off the lookup vector.
    CHECK(sphereParallax({3, 0, 0}, {0, 1, 0}, 10.0f, {1, 2, 3}).direction.z == doctest::Approx(-3.0f));
    // At 0.8 of the radius x = saturate(2.5·0.8 − 1.5) = 0.5, smoothstep 0.5: alpha 0.5.
    CHECK(sphereParallax({0, 8, 0}, {1, 0, 0}, 10.0f, {}).distanceAlpha == doctest::Approx(0.5f));
    CHECK_FALSE(sphereParallax({0, 10.5f, 0}, {1, 0, 0}, 10.0f, {}).inside);
}

TEST_CASE("Reflection captures: box parallax and its fade, by hand") {
    const Vec3f extent{10, 5, 20};
    // Along +x from x = 2 the far slab is x = 10: t = 8.
    const CaptureLookup a = boxParallax({2, 1, 0}, {1, 0, 0}, extent, 2.0f, {});
    REQUIRE(a.inside);
    CHECK(a.direction.x == doctest::Approx(10.0f));
    CHECK(a.direction.y == doctest::Approx(1.0f));
    CHECK(a.distanceAlpha == 1.0f);
    // Diagonally: x reaches 10 after 8/√½ = 11.3, y reaches 5 after 4/√½ = 5.66: the y face wins.
    const float s = std::sqrt(0.5f);
    const CaptureLookup b = boxParallax({2, 1, 0}, {s, s, 0}, extent, 2.0f, {});
    CHECK(b.direction.x == doctest::Approx(6.0f));
    CHECK(b.direction.y == doctest::Approx(5.0f));
    // 0.5 beyond the box shrunk by T/2 = 1: alpha = 1 − smoothstep(0, 1.4, 0.5) = 0.7085.
    CHECK(boxParallax({9.5f, 0, 0}, {0, 1, 0}, extent, 2.0f, {}).distanceAlpha ==
          doctest::Approx(0.708455f).epsilon(1e-4));
}

TEST_CASE("Reflection captures: two nested captures composite smallest first, under each other") {
    const Cubemap red = Cubemap::render(8, [](const Vec3f&) { return Vec3f{1, 0, 0}; });
    const Cubemap green = Cubemap::render(8, [](const Vec3f&) { return Vec3f{0, 1, 0}; });
    PreparedCapture small, large;
    small.radius = 5.0f;
    small.cube = red.view();
    large.radius = 50.0f;
    large.cube = green.view();
    large.brightness = 2.0f;
    const std::vector<PreparedCapture> captures{small, large};  // ascending radius
    const Vec3f R{0, 0, 1};
    float alpha = 1.0f;
    // Deep inside the small one: it takes everything.
    Vec3f c = compositeCaptures(captures.data(), int(captures.size()), {1, 0, 0}, R, 0.3f, alpha);
    CHECK(c.x == doctest::Approx(1.0f));
    CHECK(c.y == 0.0f);
    CHECK(alpha == 0.0f);
    // At 0.8 of its radius it fades to 0.5 and the large one (brightness 2) fills the rest.
    alpha = 1.0f;
    c = compositeCaptures(captures.data(), int(captures.size()), {4, 0, 0}, R, 0.3f, alpha);
    CHECK(c.x == doctest::Approx(0.5f));
    CHECK(c.y == doctest::Approx(1.0f));
    CHECK(alpha == doctest::Approx(0.0f));
    // Outside the small one: the large one alone; beyond both, the sky gets the weight.
    alpha = 0.6f;  // what SSR and specular occlusion left
    c = compositeCaptures(captures.data(), int(captures.size()), {20, 0, 0}, R, 0.3f, alpha);
    CHECK(c.y == doctest::Approx(1.2f));
    alpha = 1.0f;
    c = compositeCaptures(captures.data(), int(captures.size()), {60, 0, 0}, R, 0.3f, alpha);
    CHECK(alpha == 1.0f);
    CHECK(c.x + c.y + c.z == 0.0f);
}

}  // namespace fp
