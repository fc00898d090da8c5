// Per-shading-model direct-lighting BxDFs (algorithms §9.6) against hand-computed values, analytic
// bounds and the default-lit model they extend; the preintegrated-skin table against the
// properties of Penner's integral and its small-curvature asymptote.
#include "foundation/ShadingModel.h"
#include "shading/BRDF.h"
#include "shading/PreintegratedSkinLut.h"
#include "shading/ShadingModelBxDF.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace fp;

namespace {

const Vec3f kUp{0, 0, 1};

BxDFSurface surface(int model) {
    BxDFSurface s{};
    s.shadingModel = model;
    s.N = kUp;
    s.diffuseColor = {0.6f, 0.4f, 0.2f};
    s.specularColor = {0.04f, 0.04f, 0.04f};
    s.roughness = 0.5f;
    s.subsurfaceColor = {0.9f, 0.5f, 0.3f};
    s.opacity = 0.5f;
    return s;
}

/// Unit direction at polar angle theta from +z, azimuth phi (radians).
Vec3f dir(float theta, float phi = 0.0f) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

float radians(float degrees) {
    return degrees * kPiF / 180.0f;
}

bool finite(const Vec3f& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

float maxComponent(const Vec3f& v) {
    return std::max({v.x, v.y, v.z});
}
float minComponent(const Vec3f& v) {
    return std::min({v.x, v.y, v.z});
}

// Float rounding of a few dozen operations on values of order 1.
constexpr double kFloatRel = 1e-5;

void checkClose(const Vec3f& got, const Vec3f& want, double rel = kFloatRel, double abs = 1e-7) {
    for (int c = 0; c < 3; ++c)
        CHECK(std::fabs(double(got[c]) - double(want[c])) <=
              abs + rel * std::fabs(double(want[c])));
}

void checkSameTerms(const BxDFTerms& got, const BxDFTerms& want) {
    checkClose(got.diffuse, want.diffuse);
    checkClose(got.specular, want.specular);
    checkClose(got.transmission, want.transmission);
}

// Independent GGX distribution, written out rather than taken from BRDF.h.
double ggx(double a2, double NoH) {
    const double d = NoH * NoH * (a2 - 1.0) + 1.0;
    return a2 / (kPi * d * d);
}

PreintegratedSkinLut const& lut() {
    return PreintegratedSkinLut::instance();
}

/// Texel (i, j) of the skin table: the lookup at a texel centre.
Vec3f texel(int i, int j) {
    const float n = float(PreintegratedSkinLut::kSize - 1);
    return lut().sample(float(i) / n, float(j) / n);
}

}  // namespace

TEST_CASE("default lit without specular is Lambert: diffuseColor/π · NoL") {
    BxDFSurface s = surface(kDefaultLit);
    // F0 = 0 is below Unreal's 2% cut-off, so Schlick's grazing term vanishes too: no specular.
    s.specularColor = {0, 0, 0};
    const Vec3f V = dir(radians(30), 0.3f);
    for (float deg : {0.0f, 20.0f, 45.0f, 70.0f, 89.0f}) {
        const Vec3f L = dir(radians(deg), 2.0f);
        const BxDFTerms t = evaluateBxDF(s, V, L);
        checkClose(t.diffuse, s.diffuseColor * (std::cos(radians(deg)) / kPiF));
        checkClose(t.specular, {}, 0.0, 0.0);
        checkClose(t.transmission, {}, 0.0, 0.0);
    }
    // Light below the surface: nothing at all.
    const BxDFTerms below = evaluateBxDF(s, V, dir(radians(100)));
    checkClose(below.diffuse, {}, 0.0, 0.0);
    checkClose(below.specular, {}, 0.0, 0.0);
}

TEST_CASE("default lit specular is the capture renderer's SurfaceBRDF lobe × NoL") {
    BxDFSurface s = surface(kDefaultLit);
    const SurfaceBRDF brdf{s.diffuseColor, s.specularColor, s.roughness};
    const Vec3f V = dir(radians(40), 0.0f);
    for (float deg : {5.0f, 35.0f, 60.0f, 85.0f}) {
        const Vec3f L = dir(radians(deg), 2.5f);
        const float NoL = std::cos(radians(deg));
        const BxDFTerms t = evaluateBxDF(s, V, L);
        const Vec3f lobe = brdf.evaluate(s.N, V, L) - s.diffuseColor * (1.0f / kPiF);
        checkClose(t.specular, lobe * NoL);
    }
}

TEST_CASE("hard case: GGX stays finite and bounded at roughness 1 and 0 for grazing views") {
    BxDFSurface s = surface(kDefaultLit);
    s.specularColor = {1, 1, 1};  // F = 1: the largest specular any F0 gives
    // V from just above to just below the horizon: NoV = 1e-6, 1e-4, 0, −0.01.
    std::vector<Vec3f> views;
    for (float NoV : {1e-6f, 1e-4f, 0.0f, -0.01f})
        views.push_back(Vec3f{std::sqrt(1.0f - NoV * NoV), 0.0f, NoV});
    std::vector<Vec3f> lights;
    for (float theta = 0.0f; theta <= 90.0f; theta += 7.5f)
        for (float phi = 0.0f; phi < 360.0f; phi += 30.0f)
            lights.push_back(dir(radians(theta), radians(phi)));
    for (float roughness : {1.0f, 0.0f}) {
        s.roughness = roughness;
        // At roughness 1, a2 = 1: D = 1/π and Vis = 0.5/(NoL + NoV), so F·D·Vis·NoL ≤ 1/(2π).
        // At roughness 0 (clamped to 0.02, a = 0.02², a2 = a²): D ≤ 1/(π·a2) and
        // Vis·NoL ≤ 0.5/a, a finite if enormous ceiling.
        const double a = double(kMinLightRoughness) * kMinLightRoughness;
        const double bound = roughness == 1.0f ? 1.0 / (2.0 * kPi) : 0.5 / (kPi * a * a * a);
        for (const Vec3f& V : views) {
            // L = −V: H = normalize(0) degenerates to the zero vector (lit when V is below).
            std::vector<Vec3f> all = lights;
            all.push_back(-V);
            for (const Vec3f& L : all) {
                const BxDFTerms t = evaluateBxDF(s, V, L);
                REQUIRE(finite(t.diffuse));
                REQUIRE(finite(t.specular));
                CHECK(minComponent(t.specular) >= 0.0f);
                CHECK(double(maxComponent(t.specular)) <= bound * (1.0 + kFloatRel));
            }
        }
    }
}

TEST_CASE("GGX directional albedo at roughness 1 and grazing NoV = 0.01 is at most 1") {
    BxDFSurface s = surface(kDefaultLit);
    s.specularColor = {1, 1, 1};
    s.roughness = 1.0f;
    const double NoV = 0.01;
    const Vec3f V{float(std::sqrt(1.0 - NoV * NoV)), 0.0f, float(NoV)};
    // ∫ specular dω_L with dω = d(cosθ)·dφ, midpoint rule on a 256 × 64 grid.
    const int nMu = 256, nPhi = 64;
    double albedo = 0.0;
    for (int i = 0; i < nMu; ++i)
        for (int k = 0; k < nPhi; ++k) {
            const double mu = (i + 0.5) / nMu, phi = 2.0 * kPi * (k + 0.5) / nPhi;
            const double sinT = std::sqrt(1.0 - mu * mu);
            const Vec3f L{float(sinT * std::cos(phi)), float(sinT * std::sin(phi)), float(mu)};
            albedo += evaluateBxDF(s, V, L).specular.y * (1.0 / nMu) * (2.0 * kPi / nPhi);
        }
    // With F = 1, D = 1/π and Vis = 0.5/(NoL + NoV) the integrand is NoL/(2π(NoL + NoV)), so
    // the albedo is 1 − NoV·ln((1 + NoV)/NoV) = 0.9539: below 1, the energy bound. The midpoint
    // rule's error is concentrated in the first cell, where NoL/(NoL + NoV) bends on the scale
    // NoV ≈ 2.6 cells: h³·f''/24 there is ~1e-4, so 5e-4 allows for it and the float integrand.
    const double analytic = 1.0 - NoV * std::log((1.0 + NoV) / NoV);
    CHECK(albedo <= 1.0 + 5e-4);
    CHECK(albedo == doctest::Approx(analytic).epsilon(5e-4));
}

TEST_CASE("unlit reflects and transmits nothing") {
    const BxDFSurface s = surface(kUnlit);
    for (const Vec3f& L : {dir(0.0f), dir(radians(60), 1.0f), dir(radians(150), 2.0f)}) {
        const BxDFTerms t = evaluateBxDF(s, dir(radians(20)), L);
        checkClose(t.diffuse, {}, 0.0, 0.0);
        checkClose(t.specular, {}, 0.0, 0.0);
        checkClose(t.transmission, {}, 0.0, 0.0);
    }
}

TEST_CASE("two-sided foliage: no transmission lit from the front, wrapped GGX lit from behind") {
    const BxDFSurface s = surface(kTwoSidedFoliage);
    const Vec3f V = dir(radians(30));
    // N·L = 1: WrapNoL = saturate((−1 + 0.5)/2.25) = 0.
    checkClose(evaluateBxDF(s, V, kUp).transmission, {}, 0.0, 0.0);
    // N·L = −1: WrapNoL = 1.5/2.25, and −V·L = cos 30°.
    const BxDFTerms back = evaluateBxDF(s, V, -kUp);
    const double scatter = ggx(0.36, std::cos(kPi / 6.0));
    checkClose(back.transmission, s.subsurfaceColor * float(1.5 / 2.25 * scatter));
    // The surface terms vanish for a light behind the leaf.
    checkClose(back.diffuse, {}, 0.0, 0.0);
    checkClose(back.specular, {}, 0.0, 0.0);
}

TEST_CASE("subsurface: in-scatter towards the viewer and wrap-around back scatter by hand") {
    BxDFSurface s = surface(kSubsurface);
    SUBCASE("light straight through the surface (L = −V), opacity 0") {
        // InScatter = 1^12 · lerp(3, 0.1, 0) = 3; opacity 0 makes the normal term 1 whatever H
        // is, so BackScatter = AO/(2π) and lerp(B, 1, 3) = 3 − 2B = 3 − AO/π.
        s.opacity = 0.0f;
        for (float ao : {1.0f, 0.5f}) {
            s.gbufferAO = ao;
            const BxDFTerms t = evaluateBxDF(s, kUp, -kUp);
            checkClose(t.transmission, s.subsurfaceColor * (3.0f - ao / kPiF));
        }
    }
    SUBCASE("light from the side, opacity 1") {
        // L·(−V) = −cos 60° < 0: no in-scatter. H halfway between N and L at 30° from N, so
        // BackScatter = AO·cos 30°/(2π).
        s.opacity = 1.0f;
        s.gbufferAO = 0.8f;
        const BxDFTerms t = evaluateBxDF(s, kUp, dir(radians(60)));
        checkClose(t.transmission, s.subsurfaceColor * float(0.8 * std::cos(kPi / 6) / (2 * kPi)));
    }
    SUBCASE("light behind, 20° off the view-through direction, opacity 0.5") {
        // L·(−V) = cos 20°, InScatter = cos¹²20° · lerp(3, 0.1, 0.5) = 0.734; V + L lies
        // 80° from N (the half angle of the 160° between them), so the normal term is
        // saturate(cos 80°·0.5 + 0.5) and BackScatter = that/(2π).
        s.opacity = 0.5f;
        s.gbufferAO = 1.0f;
        const BxDFTerms t = evaluateBxDF(s, kUp, dir(radians(160)));
        const double inScatter = std::pow(std::cos(kPi / 9), 12.0) * 1.55;
        const double backScatter = (std::cos(4 * kPi / 9) * 0.5 + 0.5) / (2 * kPi);
        const double lobe = backScatter + (1.0 - backScatter) * inScatter;
        checkClose(t.transmission, s.subsurfaceColor * float(lobe));
    }
    SUBCASE("the surface terms are default lit") {
        BxDFSurface d = s;
        d.shadingModel = kDefaultLit;
        const Vec3f V = dir(radians(25)), L = dir(radians(50), 1.0f);
        const BxDFTerms t = evaluateBxDF(s, V, L), want = evaluateBxDF(d, V, L);
        checkClose(t.diffuse, want.diffuse);
        checkClose(t.specular, want.specular);
    }
}

TEST_CASE("preintegrated skin adds the LUT at (N·L/2 + 1/2, 1 − opacity) × subsurface colour") {
    BxDFSurface s = surface(kPreintegratedSkin);
    const Vec3f V = dir(radians(10));
    s.opacity = 0.0f;                                          // strongest scattering row
    const BxDFTerms t = evaluateBxDF(s, V, dir(radians(90)));  // light on the terminator
    checkClose(t.transmission, lut().sample(0.5f, 1.0f) * s.subsurfaceColor);
    CHECK(maxComponent(t.transmission) > 0.0f);
    s.opacity = 1.0f;  // row v = 0: a flat surface scatters nothing beyond Lambert
    checkClose(evaluateBxDF(s, V, dir(radians(90))).transmission, {}, 0.0, 0.0);
}

TEST_CASE("clear coat: no coat is default lit; a full coat adds a 4% GGX lobe and dims the base") {
    BxDFSurface s = surface(kClearCoat);
    BxDFSurface d = s;
    d.shadingModel = kDefaultLit;
    const Vec3f V = dir(radians(35)), L = dir(radians(55), 2.0f);
    s.clearCoat = 0.0f;
    s.clearCoatRoughness = 0.1f;
    checkSameTerms(evaluateBxDF(s, V, L), evaluateBxDF(d, V, L));

    // V = L = N: VoH = 1 so F_coat = 0.04; coat a2 = 0.5⁴ and NoH = 1 give D = 1/(π·a2);
    // Vis = 0.5/(NoL·1 + NoV·1) = 1/4.
    s.clearCoat = 1.0f;
    s.clearCoatRoughness = 0.5f;
    s.specularColor = {0, 0, 0};
    const BxDFTerms t = evaluateBxDF(s, kUp, kUp);
    const double a2 = 0.0625;
    const float coat = float(0.04 / (kPi * a2) * 0.25);
    checkClose(t.specular, {coat, coat, coat});
    checkClose(t.diffuse, s.diffuseColor * (0.96f / kPiF));
}

TEST_CASE("cloth: amount 0 is default lit, amount 1 is the fuzz lobe, halfway is the average") {
    BxDFSurface s = surface(kCloth);
    BxDFSurface d = s;
    d.shadingModel = kDefaultLit;
    s.opacity = 0.0f;
    const Vec3f V = dir(radians(35)), L = dir(radians(55), 2.0f);
    checkSameTerms(evaluateBxDF(s, V, L), evaluateBxDF(d, V, L));

    // V = L = N, roughness 0.5 (a2 = 0.0625): d = NoH²(1 − a2) + a2 = 1, so
    // D_InvGGX = (1 + 4a2²)/(π(1 + 4a2)); Vis_Cloth = 1/(4(1 + 1 − 1)) = 1/4; F = FuzzColor.
    s.opacity = 1.0f;
    const double a2 = 0.0625;
    const float fuzz = float((1.0 + 4.0 * a2 * a2) / (kPi * (1.0 + 4.0 * a2)) * 0.25);
    const BxDFTerms full = evaluateBxDF(s, kUp, kUp);
    checkClose(full.specular, s.subsurfaceColor * fuzz);
    checkClose(full.diffuse, s.diffuseColor * (1.0f / kPiF));

    s.opacity = 0.5f;
    const BxDFTerms half = evaluateBxDF(s, kUp, kUp);
    checkClose(half.specular, (full.specular + evaluateBxDF(d, kUp, kUp).specular) * 0.5f);
}

TEST_CASE("subsurface profile, hair, eye and later ids fall back to default lit") {
    const Vec3f V = dir(radians(20)), L = dir(radians(65), 1.5f);
    BxDFSurface d = surface(kDefaultLit);
    for (int model : {int(kSubsurfaceProfile), int(kHair), int(kEye), 10, 11}) {
        BxDFSurface s = d;
        s.shadingModel = model;
        checkSameTerms(evaluateBxDF(s, V, L), evaluateBxDF(d, V, L));
        CHECK(isDefaultLitLobe(model));
    }
    // The models with a lobe or transmission of their own (and unlit) are not, so the lanes of
    // deferred_lighting leave them to evaluateBxDF.
    CHECK(isDefaultLitLobe(kDefaultLit));
    for (int model : {int(kUnlit), int(kSubsurface), int(kPreintegratedSkin), int(kClearCoat),
                      int(kTwoSidedFoliage), int(kCloth)})
        CHECK_FALSE(isDefaultLitLobe(model));
}

TEST_CASE("skin LUT: values in [0, 1], zero for a flat surface and on the fully lit side") {
    const int n = PreintegratedSkinLut::kSize;
    CHECK(&PreintegratedSkinLut::instance() == &lut());
    float highest = 0.0f;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3f t = texel(i, j);
            // D is a weighted average of saturate(cos) ∈ [0, 1], so D − Lambert ≤ 1 − Lambert.
            CHECK(minComponent(t) >= 0.0f);
            CHECK(maxComponent(t) <= 1.0f);
            highest = std::max(highest, maxComponent(t));
        }
    CHECK(highest > 0.01f);  // the table is not empty
    for (int i = 0; i < n; ++i) {
        // v = 0 is curvature 0: the kernel stays on the tangent plane, D is Lambert exactly.
        CHECK(maxComponent(texel(i, 0)) <= 1e-3f);
        // u = 1 (NoL = 1): D averages cos x ≤ 1 over the kernel, so D − 1 < 0 clamps to 0.
        CHECK(maxComponent(texel(n - 1, i)) == 0.0f);
    }
    // Between texels the lookup interpolates: clamped outside [0, 1], NaN reads as 0.
    checkClose(lut().sample(-1.0f, 2.0f), texel(0, n - 1), 0.0, 0.0);
    checkClose(lut().sample(NAN, NAN), texel(0, 0), 0.0, 0.0);
}

TEST_CASE("skin LUT: diffusion only spreads light across the terminator") {
    const int n = PreintegratedSkinLut::kSize, mid = (n - 1) / 2;  // u = 0.5 is texel `mid`
    for (int j = 1; j < n; ++j) {
        // The table rises from the shadow side to the terminator and falls back to 0 on the lit
        // side: D is Lambert blurred around the circle, and blurring lifts Lambert only where
        // its kink is (concave cos on the lit side is lowered, which the clamp turns into 0).
        for (int i = 1; i < n; ++i)
            for (int c = 0; c < 3; ++c) {
                if (i <= mid)
                    CHECK(texel(i, j)[c] >= texel(i - 1, j)[c]);
                else
                    CHECK(texel(i, j)[c] <= texel(i - 1, j)[c]);
            }
        // More curvature (larger v) blurs over a wider angle: more light past the terminator.
        const Vec3f here = texel(mid, j), below = texel(mid, j - 1);
        for (int c = 0; c < 3; ++c)
            CHECK(here[c] > below[c]);
        // Skin's red keeps weight on wide Gaussians, blue does not: red bleeds furthest.
        CHECK(here.x > here.y);
        CHECK(here.y > here.z);
    }
}

TEST_CASE("skin LUT at the terminator matches the small-curvature asymptote of Penner's integral") {
    // For r ≫ σ, a Gaussian of variance σ² on the ring is a 1D Gaussian in x of width σ/r and
    // total weight w/(r·σ·√(2π)); at the terminator saturate(cos(π/2 + x)) ≈ max(−x, 0), whose
    // mean is (σ/r)/√(2π). So D(π/2) ≈ Σ w / (r·√(2π)·Σ w/σ) with Σ w = 1 per channel. The
    // six-Gaussian skin profile of d'Eon & Luebke (GPU Gems 3, ch. 14), written out here
    // independently of the table's source.
    const double variance[6] = {0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41};
    const double weight[6][3] = {{0.233, 0.455, 0.649}, {0.100, 0.336, 0.344}, {0.118, 0.198, 0.0},
                                 {0.113, 0.007, 0.007}, {0.358, 0.004, 0.0},   {0.078, 0.0, 0.0}};
    for (float v : {1.0f / 64, 1.0f / 8, 1.0f / 4}) {
        const double radius = PreintegratedSkinLut::kMinRadiusMm / v;
        const Vec3f got = lut().sample(0.5f, v);
        for (int c = 0; c < 3; ++c) {
            double sharpness = 0.0;
            for (int g = 0; g < 6; ++g)
                sharpness += weight[g][c] / std::sqrt(variance[g]);
            const double asymptote = 1.0 / (radius * std::sqrt(2.0 * kPi) * sharpness);
            // The neglected terms (x³/6 of sin x, x³/24 of the chord) are relative (σ/r)²/6
            // per Gaussian, weighted by its share w of the result: ≈ 0.3% for red at r = 8 mm
            // (σ = 1.4 and 2.7 mm carry 44% of its weight), far less for green and blue, and
            // less at larger r. 0.5% covers that and the quadrature's 1e-4.
            CHECK(double(got[c]) == doctest::Approx(asymptote).epsilon(5e-3));
        }
    }
}

TEST_CASE("skin LUT is smooth: second differences bounded by the table's resolution") {
    const int n = PreintegratedSkinLut::kSize, mid = (n - 1) / 2;
    const double h = 1.0 / (n - 1);
    double maxU = 0.0, maxUAtTerminator = 0.0, maxV = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 1; i + 1 < n; ++i)
            for (int c = 0; c < 3; ++c) {
                const double d2 = std::fabs(double(texel(i - 1, j)[c]) - 2.0 * texel(i, j)[c] +
                                            texel(i + 1, j)[c]);
                double& worst = i == mid ? maxUAtTerminator : maxU;
                worst = std::max(worst, d2);
            }
    for (int j = 1; j + 1 < n; ++j)
        for (int i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c)
                maxV = std::max(maxV, std::fabs(double(texel(i, j - 1)[c]) - 2.0 * texel(i, j)[c] +
                                                texel(i, j + 1)[c]));
    // Along u: Δ²f = h·∫ f''·hat over two cells. Lambert's kink at u = 0.5 (slope 0 → 2 in u)
    // is subtracted exactly at the terminator texel and gives at most 2h there. Elsewhere the
    // only bend is D's blurred copy of that kink, whose slope rises by at most 1 on either side
    // of the terminator, so Δ² ≤ h. Quadrature ripple of amplitude A would add ~4A.
    CHECK(maxUAtTerminator <= 2.0 * h);
    CHECK(maxU <= h);
    // Along v (curvature) the table grows almost linearly (the asymptote above) to at most
    // ~0.05, so f_vv is of the order of that range: Δ² = h²·f_vv. Allowing |f_vv| ≤ 4, i.e.
    // Δ² ≤ 4h² ≈ 1e-3, leaves margin for the bend near v = 0 on the shadow side, yet a kink or
    // a ripple of amplitude 2.5e-4 at texel scale fails it.
    CHECK(maxV <= 4.0 * h * h);
}
