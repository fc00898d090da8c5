// The reference tracer against analytic answers (issue 3): white furnace, AO of open and closed
// geometry, a point light's irradiance seen through a mirror, the form factor of an emitting
// square, shadows of an occluder, 1/√N noise, and bit-identical reruns.
#include "reference/TruthRenderer.h"
#include "tests/support/TestScenes.h"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>

using namespace fp;

namespace {

using test::lambert;

/// The six faces of the cube [-h, h]³ around `c`, all with material `material`.
void addCube(Scene& s, const Vec3d& c, double h, int material) {
    const Vec3d X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
    s.meshes.push_back(test::quad(c + X * h, Y, Z, h, material));
    s.meshes.push_back(test::quad(c - X * h, Z, Y, h, material));
    s.meshes.push_back(test::quad(c + Y * h, Z, X, h, material));
    s.meshes.push_back(test::quad(c - Y * h, X, Z, h, material));
    s.meshes.push_back(test::quad(c + Z * h, X, Y, h, material));
    s.meshes.push_back(test::quad(c - Z * h, Y, X, h, material));
}

FrameCamera camera(const Vec3d& eye, const Vec3d& target, const Vec3d& up, int w, int h,
                   double fov = 60.0) {
    FrameCamera cam;
    cam.current = CameraView::lookAt(eye, target, up, fov, w, h, 0.01);
    return cam;
}

TruthResult renderTruth(const Scene& s, const FrameCamera& cam, int spp, double aoRadius = 1e9) {
    TruthSettings ts;
    ts.samplesPerPixel = spp;
    ts.aoRadius = aoRadius;
    return TruthRenderer(s, cam, ts).render();
}

/// Checks a layer channel against an expected value pixel by pixel, in units of each pixel's
/// own standard error: with Gaussian errors 99.7 % of pixels lie within 3σ, and the mean over
/// all pixels within 4σ/√n.
template <class Expected>
void checkWithinNoise(const TruthResult& r, const std::string& layer, int channel, Expected expected,
                      int minPixels) {
    const Plane& mean = r.layers.at(layer).plane(channel);
    const Plane& err = r.layers.at(layer + ".StdErr").plane(channel);
    int n = 0, within = 0;
    double sumDiff = 0, sumVar = 0;
    for (int y = 0; y < mean.height(); ++y)
        for (int x = 0; x < mean.width(); ++x) {
            double e;
            if (!expected(x, y, e)) continue;
            const double d = mean.at(x, y) - e, s = err.at(x, y);
            ++n;
            within += std::abs(d) <= 3.0 * s + 1e-6 * std::abs(e) ? 1 : 0;
            sumDiff += d;
            sumVar += s * s;
        }
    REQUIRE(n >= minPixels);
    // 99.7 % for Gaussian errors; path-traced samples are skewed (rare bright paths), so the
    // per-pixel t-statistic has heavier tails: ask for 95 %.
    CHECK(double(within) / n >= 0.95);
    const double meanDiff = sumDiff / n, meanErr = std::sqrt(sumVar) / n;
    CHECK(std::abs(meanDiff) <= 4.0 * meanErr + 1e-6);
}

// Form factor from a differential area to a parallel a×b rectangle at height c with one corner
// straight above it (Howell's catalogue, configuration B-3).
double cornerFormFactor(double a, double b, double c) {
    const double X = a / c, Y = b / c;
    const double sx = std::sqrt(1 + X * X), sy = std::sqrt(1 + Y * Y);
    return (X / sx * std::atan(Y / sx) + Y / sy * std::atan(X / sy)) / (2.0 * kPi);
}

/// Form factor from the floor point under pixel (x, y) of a camera looking down at the floor
/// (y = 0) to the square [−half, half]² at height c, as four corner rectangles around the point's
/// projection; false for a point within 0.5 of the square's edge or outside it.
bool squareFormFactor(const CameraView& cv, double half, double c, int x, int y, double& f) {
    const Vec3d d = cv.rayDirection(x, y);
    const Vec3d p = cv.position + d * (-cv.position.y / d.y);
    if (std::abs(p.x) > half - 0.5 || std::abs(p.z) > half - 0.5) return false;
    f = cornerFormFactor(half - p.x, half - p.z, c) + cornerFormFactor(half + p.x, half - p.z, c) +
        cornerFormFactor(half - p.x, half + p.z, c) + cornerFormFactor(half + p.x, half + p.z, c);
    return true;
}

}  // namespace

TEST_SUITE("truth") {

TEST_CASE("white furnace: a closed box of albedo a glowing Le holds Le/(1−a) everywhere") {
    for (float albedo : {0.5f, 0.8f}) {
        Scene s;
        s.materials.push_back(lambert(albedo, 1.0f));
        addCube(s, {0, 0, 0}, 10.0, 0);
        const auto cam = camera({1, 2, 3}, {4, -1, 9}, {0, 1, 0}, 24, 16, 90.0);
        const TruthResult r = renderTruth(s, cam, 64);
        CAPTURE(albedo);
        const double full = 1.0 / (1.0 - albedo);
        for (int c = 0; c < 3; ++c) {
            checkWithinNoise(r, "Truth.DiffuseIndirectFull", c,
                             [&](int, int, double& e) { return e = full, true; }, 24 * 16);
            // One bounce: the other walls hold only their emission (no lights in the scene).
            checkWithinNoise(r, "Truth.DiffuseIndirectOneBounce", c,
                             [&](int, int, double& e) { return e = 1.0, true; }, 24 * 16);
            // The beauty: Le + a·full (no lights: no direct light, no specular lobe).
            checkWithinNoise(r, "Truth.Combined", c,
                             [&](int, int, double& e) { return e = full, true; }, 24 * 16);
        }
    }
}

TEST_CASE("AO is 1 everywhere on an open plane and 0 everywhere inside a closed box") {
    const Scene open = test::floorScene();
    const auto above = camera({0, 30, -30}, {0, 0, 10}, {0, 1, 0}, 24, 16);
    const TruthResult a = renderTruth(open, above, 16, 1e6);
    Scene closed;
    closed.materials.push_back(lambert(0.5f));
    addCube(closed, {0, 0, 0}, 10.0, 0);
    const TruthResult b = renderTruth(closed, camera({1, 2, 3}, {4, -1, 9}, {0, 1, 0}, 24, 16), 16, 1e6);
    const Image& depthless = a.layers.at("Truth.DiffuseIndirectFull");  // 0 on sky and on the plane
    int plane = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x) {
            const Vec3d d = above.current.rayDirection(x, y);
            const Vec3d p = above.current.position + d * (-above.current.position.y / d.y);
            if (d.y >= 0 || std::abs(p.x) > 99 || std::abs(p.z) > 99) continue;  // sky pixel
            ++plane;
            CHECK(a.layers.at("Truth.AO").plane(0).at(x, y) == 1.0f);
            CHECK(a.layers.at("Truth.AO.StdErr").plane(0).at(x, y) == 0.0f);
            CHECK(a.layers.at("Truth.AOAnyDistance").plane(0).at(x, y) == 1.0f);
            CHECK(depthless.plane(0).at(x, y) == 0.0f);  // nothing to bounce light from
            CHECK(b.layers.at("Truth.AO").plane(0).at(x, y) == 0.0f);
            CHECK(b.layers.at("Truth.AOAnyDistance").plane(0).at(x, y) == 0.0f);
        }
    CHECK(plane > 100);
}

TEST_CASE("AO at a concave edge is one half, for pixel centres on the edge and at grazing incidence") {
    // A floor (y = 0, x ≤ 0) meets a wall (x = 0, y ≥ 0) 2000 units across. Whichever of the two
    // a point near the edge lies on, the other covers exactly the half of its cosine-weighted
    // hemisphere that leans towards it, out to a height of 2000 units: a point within 10 units
    // of the edge sees past the wall's top only in a cone of cos² < 10⁻⁴, so AO = 0.5 to 10⁻⁴.
    // The camera lies in a plane through the edge, so the image's centre column looks at the
    // edge itself: those pixel centres lie on both surfaces to within float rounding, the case
    // that a fixed normal offset gets wrong (the ray starts on, or behind, the other surface).
    Scene s;
    s.materials.push_back(lambert(0.5f));
    const Vec3d X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
    s.meshes.push_back(test::quad({-1000, 0, 0}, Z, X, 1000));  // normal +y
    s.meshes.push_back(test::quad({0, 1000, 0}, Z, Y, 1000));   // normal −x
    for (const double height : {10.0, 0.5}) {  // 45° and about 3° above the floor
        CAPTURE(height);
        const auto cam = camera({-10, height, 0}, {0, 0, 0}, Z, 9, 33, 40.0);
        const TruthResult r = renderTruth(s, cam, 256);
        int onEdge = 0;
        checkWithinNoise(r, "Truth.AO", 0, [&](int x, int, double& e) {
            onEdge += x == 4 ? 1 : 0;
            return e = 0.5, true;
        }, 9 * 33);
        CHECK(onEdge == 33);
        // The edge column alone: its mean over 33 pixels × 256 rays lies within 4σ of one half.
        double sum = 0, var = 0;
        for (int y = 0; y < 33; ++y) {
            sum += r.layers.at("Truth.AO").plane(0).at(4, y);
            var += std::pow(r.layers.at("Truth.AO.StdErr").plane(0).at(4, y), 2.0f);
        }
        CHECK(std::abs(sum / 33 - 0.5) <= 4.0 * std::sqrt(var) / 33);
        // With no radius the wall occludes at any distance: the same half.
        checkWithinNoise(r, "Truth.AOAnyDistance", 0, [&](int, int, double& e) {
            return e = 0.5, true;
        }, 9 * 33);
    }
}

TEST_CASE("Truth.AO counts occluders within the radius, Truth.AOAnyDistance at any distance") {
    // A floor point 10 units from a wall 2000 units across: with an AO radius of 5 the wall is out
    // of reach (AO 1 exactly); at any distance it takes the cosine-weighted half leaning towards it,
    // less the cone over its top (cos² < 10⁻⁴): 0.5.
    Scene s;
    s.materials.push_back(lambert(0.5f));
    const Vec3d X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
    s.meshes.push_back(test::quad({-1000, 0, 0}, Z, X, 1000));  // floor, normal +y
    s.meshes.push_back(test::quad({0, 1000, 0}, Z, Y, 1000));   // wall x = 0, normal −x
    // Looking straight down at floor points 10 ± 1 units from the wall.
    const auto cam = camera({-10, 5, 0}, {-10, 0, 0}, X, 8, 8, 20.0);
    const TruthResult r = renderTruth(s, cam, 256, 5.0);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) CHECK(r.layers.at("Truth.AO").plane(0).at(x, y) == 1.0f);
    checkWithinNoise(r, "Truth.AOAnyDistance", 0, [&](int, int, double& e) {
        return e = 0.5, true;
    }, 64);
}

TEST_CASE("a point light's irradiance I·cosθ/r² on a Lambert wall, seen in a mirror floor") {
    // A perfect mirror floor (metal, base colour 1: Schlick F = 1) reflects the wall; the
    // specular truth at a floor pixel is the wall's radiance ρ/π · I·cosθ/r² at the mirrored
    // point. GGX at roughness 0 is clamped to α = 4·10⁻⁴ (BRDF.h), a cone of ~10⁻³ rad whose
    // smoothing of the wall's radiance is below 10⁻³ relative. The light is a spot whose inner
    // cone (full intensity: a point light there) covers the tested part of the wall and whose
    // outer cone misses the floor, so no caustic through the mirror adds to the wall; the
    // mirror cannot show the wall to itself (rays leaving the wall downwards reflect away).
    Scene s;
    s.materials.push_back(test::mirror());
    s.materials.push_back(lambert(0.6f));
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 100.0, 0));  // floor y = 0
    s.meshes.push_back(test::quad({0, 50, 60}, {1, 0, 0}, {0, 1, 0}, 50.0, 1));  // wall z = 60
    Light l;
    l.type = LightType::Spot;
    l.position = {10, 40, 20};
    l.direction = {0, 0, 1};
    l.innerConeDegrees = 30.0f;
    l.outerConeDegrees = 35.0f;  // the floor is 45° or more off the axis
    l.intensity = 5000.0f;
    s.lights.push_back(l);
    const auto cam = camera({0, 20, -40}, {0, 5, 30}, {0, 1, 0}, 32, 24, 50.0);
    const TruthResult r = renderTruth(s, cam, 4);
    const CameraView& c = cam.current;
    int checked = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const Vec3d d = c.rayDirection(x, y);
            if (d.y >= 0) continue;
            const Vec3d p = c.position + d * (-c.position.y / d.y);  // on the floor
            const Vec3d m{d.x, -d.y, d.z};                           // mirrored direction
            const double t = (60.0 - p.z) / m.z;
            const Vec3d w = p + m * t;  // point on the wall
            if (m.z <= 0 || std::abs(w.x) > 45 || w.y < 5 || w.y > 95) continue;
            const Vec3d toLight = l.position - w;
            const double r2 = dot(toLight, toLight), cosTheta = -toLight.z / std::sqrt(r2);
            if (cosTheta < std::cos(29.0 * kPi / 180.0)) continue;  // outside the inner cone
            const double expected = 0.6 / kPi * l.intensity * cosTheta / r2;
            CHECK(r.layers.at("Truth.Specular").plane(1).at(x, y) ==
                  doctest::Approx(expected).epsilon(2e-3));
            ++checked;
        }
    CHECK(checked > 50);
}

TEST_CASE("diffuse indirect under an emitting square equals Le × the point-to-rectangle form factor") {
    const double c = 10.0, half = 6.0;  // square [-6, 6]² at height 10
    Scene s;
    s.materials.push_back(lambert(0.5f));
    s.materials.push_back(lambert(0.0f, 2.0f));  // black emitter: its radiance is exactly Le
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 100.0, 0));
    s.meshes.push_back(test::quad({0, c, 0}, {1, 0, 0}, {0, 0, 1}, half, 1));
    // Looking straight down from between the two planes.
    const auto cam = camera({0, 4, 0}, {0, 0, 0}, {0, 0, 1}, 33, 33, 90.0);
    const TruthResult r = renderTruth(s, cam, 64);
    const CameraView& cv = cam.current;
    auto expected = [&](int x, int y, double& e) {
        return squareFormFactor(cv, half, c, x, y, e) ? (e *= 2.0, true) : false;
    };
    double centre;
    expected(16, 16, centre);
    CHECK(centre == doctest::Approx(2.0 * 4.0 * cornerFormFactor(half, half, c)));
    checkWithinNoise(r, "Truth.DiffuseIndirectOneBounce", 0, expected, 200);
    // Nothing reflects back into the floor's hemisphere except the black emitter: Full = OneBounce.
    checkWithinNoise(r, "Truth.DiffuseIndirectFull", 0, expected, 200);
}

TEST_CASE("a rect light with an emissive shape is counted once: direct in Combined, not indirect") {
    // The scene of the form-factor test, lit by a rect light of radiance Le over the emitting
    // square, which is the light's visible shape. The floor's direct light is ρ·Le·F (F the
    // form factor above); its indirect light is 0: the square, black, reflects nothing and its
    // emission is the light's. Unmarked, the square would also be an emitter: one-bounce Le·F
    // and a beauty of 2·ρ·Le·F, the light counted twice.
    const double c = 10.0, half = 6.0, Le = 2.0, rho = 0.5;
    for (const bool marked : {true, false}) {
        CAPTURE(marked);
        Scene s;
        s.materials.push_back(lambert(float(rho)));
        s.materials.push_back(lambert(0.0f, float(Le)));
        s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 100.0, 0));
        s.meshes.push_back(test::quad({0, c, 0}, {1, 0, 0}, {0, 0, 1}, half, 1));
        Light l;
        l.type = LightType::Rect;
        l.color = {float(Le), float(Le), float(Le)};
        l.position = {0, c, 0};
        l.halfU = {half, 0, 0};
        l.halfV = {0, 0, half};  // emits along halfU × halfV = −y, onto the floor
        s.lights.push_back(l);
        if (marked) s.meshes[1].shapeOf = 0;
        const auto down = camera({0, 4, 0}, {0, 0, 0}, {0, 0, 1}, 33, 33, 90.0);
        const TruthResult r = renderTruth(s, down, 64);
        const CameraView& cv = down.current;
        auto formFactor = [&](int x, int y, double& f) { return squareFormFactor(cv, half, c, x, y, f); };
        const double copies = marked ? 1.0 : 2.0;
        checkWithinNoise(r, "Truth.Combined", 0, [&](int x, int y, double& e) {
            return formFactor(x, y, e) ? (e *= copies * rho * Le, true) : false;
        }, 200);
        checkWithinNoise(r, "Truth.DiffuseIndirectOneBounce", 0, [&](int x, int y, double& e) {
            return formFactor(x, y, e) ? (e *= (copies - 1.0) * Le, true) : false;
        }, 200);
        if (marked) {
            // Exactly 0, not just within noise: nothing samples or gathers the shape.
            const Plane& one = r.layers.at("Truth.DiffuseIndirectFull").plane(0);
            for (int y = 0; y < 33; ++y)
                for (int x = 0; x < 33; ++x) CHECK(one.at(x, y) == 0.0f);
            // The camera still sees the light's shape: Combined is its emission there.
            const auto up = camera({0, 4, 0}, {0, 10, 0}, {0, 0, 1}, 9, 9, 60.0);
            const TruthResult u = renderTruth(s, up, 4);
            for (int y = 0; y < 9; ++y)
                for (int x = 0; x < 9; ++x)
                    CHECK(u.layers.at("Truth.Combined").plane(0).at(x, y) == doctest::Approx(Le));
        }
    }
}

TEST_CASE("Truth.ReflectedEmitter is 1 where a mirror reflects an emitter and 0 elsewhere") {
    // A mirror floor under an emitting square (y = 30, half-size 10, centred at z = 20), marked
    // as a light's visible shape: the truth's specular leaves it out (the light's own specular
    // counts it), and ReflectedEmitter marks the pixels whose lobe sees it — at roughness 0
    // (α = 4·10⁻⁴, a cone of ~10⁻³ rad) every sample or none, away from the square's edges.
    Scene s;
    s.materials.push_back(test::mirror());
    s.materials.push_back(lambert(0.0f, 5.0f));
    s.meshes.push_back(test::quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 200.0, 0));
    s.meshes.push_back(test::quad({0, 30, 20}, {1, 0, 0}, {0, 0, 1}, 10.0, 1));
    Light l;
    l.type = LightType::Rect;
    l.color = {5, 5, 5};
    l.position = {0, 30, 20};
    l.halfU = {10, 0, 0};
    l.halfV = {0, 0, 10};
    s.lights.push_back(l);
    s.meshes[1].shapeOf = 0;
    const auto cam = camera({0, 10, -30}, {0, 0, 20}, {0, 1, 0}, 48, 36, 60.0);
    const TruthResult r = renderTruth(s, cam, 8);
    const Plane& seen = r.layers.at("Truth.ReflectedEmitter").plane(0);
    const CameraView& c = cam.current;
    int inside = 0, outside = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
            const Vec3d d = c.rayDirection(x, y);
            if (d.y >= 0) continue;
            const Vec3d p = c.position + d * (-c.position.y / d.y);  // on the floor
            if (std::abs(p.x) > 190 || std::abs(p.z) > 190) continue;
            const Vec3d m{d.x, -d.y, d.z};
            const Vec3d q = p + m * (30.0 / m.y);  // the mirror ray at the square's height
            const double margin = std::max(std::abs(q.x) - 10.0, std::abs(q.z - 20.0) - 10.0);
            if (margin < -0.5) {
                CHECK(seen.at(x, y) == 1.0f);
                ++inside;
            } else if (margin > 0.5) {
                CHECK(seen.at(x, y) == 0.0f);
                ++outside;
            }
        }
    CHECK(inside > 40);
    CHECK(outside > 200);
}

TEST_CASE("a point light's shadow truth is exactly 1 in light and 0 behind an occluder") {
    Scene s = test::floorScene();
    s.materials.push_back(lambert(0.5f));
    s.meshes.push_back(test::quad({0, 10, 0}, {1, 0, 0}, {0, 0, 1}, 5.0, 1));  // occluder
    Light l;
    l.name = "key light";
    l.type = LightType::Point;
    l.position = {0, 30, 0};
    s.lights.push_back(l);
    const auto cam = camera({0, 40, -40}, {0, 0, 0}, {0, 1, 0}, 32, 32, 70.0);
    const TruthResult r = renderTruth(s, cam, 4);
    REQUIRE(r.layers.count("Truth.Shadow.key_light"));
    const Plane& vis = r.layers.at("Truth.Shadow.key_light").plane(0);
    const CameraView& cv = cam.current;
    int lit = 0, shadowed = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const Vec3d d = cv.rayDirection(x, y);
            // What the pixel sees first: the occluder (y = 10) or the floor.
            const Vec3d q = cv.position + d * ((10.0 - cv.position.y) / d.y);
            if (std::abs(q.x) <= 5.0 && std::abs(q.z) <= 5.0) continue;
            const Vec3d p = cv.position + d * (-cv.position.y / d.y);
            if (std::abs(p.x) > 100 || std::abs(p.z) > 100) continue;
            // The shadow is the occluder projected from the light: scale 30/20 = 1.5 → ±7.5.
            const double m = std::max(std::abs(p.x), std::abs(p.z));
            if (std::abs(m - 7.5) < 0.5) continue;  // a pixel's width from the edge
            if (m < 7.5) {
                CHECK(vis.at(x, y) == 0.0f);
                ++shadowed;
            } else {
                CHECK(vis.at(x, y) == 1.0f);
                ++lit;
            }
        }
    CHECK(lit > 50);
    CHECK(shadowed > 20);
}

TEST_CASE("standard errors shrink as 1/√N") {
    Scene s;
    s.materials.push_back(lambert(0.7f, 1.0f));
    s.materials.push_back(lambert(0.3f));
    addCube(s, {0, 0, 0}, 10.0, 1);
    s.meshes.push_back(test::quad({0, 5, 0}, {1, 0, 0}, {0, 0, 1}, 2.0, 0));  // a small emitter
    const auto cam = camera({0, 0, -9}, {0, 0, 10}, {0, 1, 0}, 32, 32, 90.0);
    auto rmsStdErr = [&](int spp, const std::string& layer) {
        const TruthResult r = renderTruth(s, cam, spp, 5.0);
        const Plane& e = r.layers.at(layer + ".StdErr").plane(0);
        double sum = 0;
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) sum += double(e.at(x, y)) * e.at(x, y);
        return std::sqrt(sum / (32 * 32));
    };
    // E[s²] = σ² for the Bessel-corrected estimate, so the RMS of the standard errors halves
    // exactly in expectation from 16 to 64 samples; 10 % covers the scatter over 1024 pixels.
    for (const std::string layer : {"Truth.DiffuseIndirectFull", "Truth.AO"}) {
        CAPTURE(layer);
        const double r16 = rmsStdErr(16, layer), r64 = rmsStdErr(64, layer);
        CHECK(r16 > 0.0);
        CHECK(r16 / r64 == doctest::Approx(2.0).epsilon(0.1));
    }
}

TEST_CASE("the same seed gives the same truth bit for bit, on 1 or 2 threads") {
    Scene s;
    s.materials.push_back(lambert(0.6f, 0.5f));
    addCube(s, {0, 0, 0}, 10.0, 0);
    Light l;
    l.type = LightType::Rect;
    l.position = {0, 9, 0};
    s.lights.push_back(l);
    const auto cam = camera({1, 2, 3}, {4, -1, 9}, {0, 1, 0}, 80, 70, 90.0);  // several tiles
    const TruthResult a = renderTruth(s, cam, 8);
    TruthResult b;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        b = renderTruth(s, cam, 8);
    }
    REQUIRE(a.layers.size() == b.layers.size());
    for (const auto& [layer, img] : a.layers)
        for (int c = 0; c < img.channelCount(); ++c) {
            const std::string& name = layer;  // (clang 14 cannot capture a structured binding)
            CAPTURE(name);
            CHECK(test::sameBits(img.plane(c), b.layers.at(name).plane(c)));
        }
}

}  // TEST_SUITE
