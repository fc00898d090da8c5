// The screen-space kernels that several passes share (screenspace/): the denoisers' bilateral
// weight, last frame's pixel position, the per-pixel surface and the GBuffer port helpers, each
// against values worked out by hand or through the camera's own definitions.
#include "screenspace/Bilateral.h"
#include "screenspace/GBuffer.h"
#include "screenspace/Reprojection.h"
#include "screenspace/Surface.h"
#include "foundation/FloatToInt.h"
#include "foundation/ShadingModel.h"
#include "foundation/ExpLog.h"
#include "foundation/SinCos.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>

namespace fp {

namespace {

// A receiver at (1, 2, 3) facing +y, the plane y = 2.
Surface receiver() {
    Surface s;
    s.valid = true;
    s.position = {1, 2, 3};
    s.normal = {0, 1, 0};
    s.radius = 0.5f;
    return s;
}

CameraView testCamera(const Vec3d& eye = {0, 0, 0}, const Vec3d& target = {0, 0, 100}) {
    return CameraView::lookAt(eye, target, {0, 1, 0}, 60.0, 64, 48, 10.0);
}

// A 64×48 GBuffer of one depth, one (unnormalised) normal and one shading model.
struct FlatGBuffer {
    Plane depth{64, 48, 250.0f};
    Image normal{64, 48, {"X", "Y", "Z"}};
    Plane shadingModel{64, 48, float(kDefaultLit)};
    explicit FlatGBuffer(const Vec3f& n) {
        for (int c = 0; c < 3; ++c)
            normal.plane(c) = Plane(64, 48, n[c]);
    }
    SurfaceInputs inputs() const { return {depth, normal, shadingModel}; }
};

// How many float steps (at b's magnitude) a is from the reference b.
int ulpsApart(float a, float b) {
    if (a == b)
        return 0;
    const float step = std::nextafter(std::fabs(b), std::numeric_limits<float>::infinity()) - std::fabs(b);
    return int(std::ceil(std::fabs(double(a) - double(b)) / double(step)));
}

}  // namespace

TEST_CASE("roundHalfAwayToInt is std::lround: halves away from zero, and every float in between") {
    // The shadow denoiser's tap offsets use it in place of lround; its taps must not move.
    for (float v : {0.0f, -0.0f, 0.5f, -0.5f, 1.5f, -1.5f, 2.5f, -2.5f, 0.49999997f, -0.49999997f,
                    31.5f, -31.5f, 8388607.5f, -8388607.5f, 8388609.0f, 1e9f, -1e9f})
        CHECK(roundHalfAwayToInt(v) == std::lround(v));
    // Every float of [−64, 64] at a step of 2⁻¹⁶ and the ulps around each half.
    int mismatches = 0;
    for (int i = -64 * 65536; i <= 64 * 65536; ++i) {
        const float v = float(i) / 65536.0f;
        for (float w : {v, std::nextafter(v, -INFINITY), std::nextafter(v, INFINITY)})
            mismatches += roundHalfAwayToInt(w) != std::lround(w);
    }
    CHECK(mismatches == 0);
}

TEST_CASE("sinCos is within 1 ulp of the correctly rounded sine and cosine") {
    // The double evaluation is accurate to ~3·10⁻¹⁴ relative, far below half a float ulp (6·10⁻⁸),
    // so each result is the correctly rounded float unless the true value lies that close to a
    // rounding midpoint, and then its neighbour: never more than 1 ulp away. The reference is
    // std::sin/std::cos in double (within 1 double ulp) rounded to float once.
    int worst = 0, inexact = 0, count = 0;
    const float twoPi = 6.28318531f;
    for (int i = -1000003; i <= 1000003; ++i) {
        const float angle = twoPi * float(i) / 1000003.0f;
        float s, c;
        sinCos(angle, s, c);
        const float sRef = float(std::sin(double(angle))), cRef = float(std::cos(double(angle)));
        worst = std::max({worst, ulpsApart(s, sRef), ulpsApart(c, cRef)});
        inexact += (s != sRef) + (c != cRef);
        count += 2;
    }
    CHECK(worst <= 1);
    CHECK(inexact * 10000 < count);  // off by one in fewer than 1 result in 10⁴
    float s, c;
    sinCos(0.0f, s, c);
    CHECK(s == 0.0f);
    CHECK(c == 1.0f);
}

TEST_CASE("log2Float and powFloat are within 1 ulp of the correctly rounded values") {
    // As sinCos: evaluated in double (truncation below 10⁻¹⁸ relative, rounding a few double
    // ulps), rounded to float once; the reference is std::log2/std::pow in double rounded once.
    int worst = 0, inexact = 0, count = 0;
    // Arguments over 2⁻⁶⁰ … 2⁶⁰ (log-spaced), exponents over [−8, 8]: the passes' ranges and more.
    for (int i = 0; i <= 400000; ++i) {
        const float x = float(std::exp2(-60.0 + 120.0 * i / 400000.0));
        const float y = -8.0f + 16.0f * float(i % 1009) / 1008.0f;
        const float l = log2Float(x), lRef = float(std::log2(double(x)));
        const float p = powFloat(x, y), pRef = float(std::pow(double(x), double(y)));
        worst = std::max(worst, ulpsApart(l, lRef));
        if (std::isfinite(pRef) && pRef > 1e-30f) {
            worst = std::max(worst, ulpsApart(p, pRef));
            inexact += p != pRef;
            ++count;
        }
        inexact += l != lRef;
        ++count;
    }
    CHECK(worst <= 1);
    CHECK(inexact * 1000 < count);
    // Exact where the result is: powers of two, and the special cases Lagarde's term meets.
    CHECK(log2Float(128.0f) == 7.0f);
    CHECK(log2Float(0.001f) == float(std::log2(0.001)));
    CHECK(powFloat(2.0f, 10.0f) == 1024.0f);
    CHECK(powFloat(0.0f, 0.25f) == 0.0f);
    CHECK(powFloat(0.0f, 0.0f) == 1.0f);
    CHECK(powFloat(1.5f, 0.0f) == 1.0f);
    CHECK(std::isnan(powFloat(-1.0f, 0.5f)));
    CHECK(log2Float(0.0f) == -std::numeric_limits<float>::infinity());
}

TEST_CASE("bilateral weight: plane distance and normal⁴") {
    const Surface ref = receiver();
    const Vec3f up{0, 1, 0};
    const float D = 2.0f;
    // Anywhere on the receiver's plane with its normal: full weight, however far along the plane.
    CHECK(bilateralWeight(ref, {1, 2, 3}, up, D) == 1.0f);
    CHECK(bilateralWeight(ref, {40, 2, -7}, up, D) == 1.0f);
    // Half the tolerance off the plane, in front or behind: 1 − ½.
    CHECK(bilateralWeight(ref, {1, 3, 3}, up, D) == 0.5f);
    CHECK(bilateralWeight(ref, {5, 1, 0}, up, D) == 0.5f);
    // At or beyond the tolerance: nothing (saturate, never negative).
    CHECK(bilateralWeight(ref, {1, 0, 3}, up, D) == 0.0f);
    CHECK(bilateralWeight(ref, {1, -10, 3}, up, D) == 0.0f);
    // A normal 60° away: cos 60° = ½, to the fourth = 1/16.
    const Vec3f tilted{std::sqrt(3.0f) / 2.0f, 0.5f, 0.0f};
    CHECK(bilateralWeight(ref, {1, 2, 3}, tilted, D) == doctest::Approx(0.0625f).epsilon(1e-6));
    // Perpendicular and back-facing normals: nothing.
    CHECK(bilateralWeight(ref, {1, 2, 3}, {1, 0, 0}, D) == 0.0f);
    CHECK(bilateralWeight(ref, {1, 2, 3}, {0, -1, 0}, D) == 0.0f);
    // Both factors multiply: ½ off the plane × 1/16.
    CHECK(bilateralWeight(ref, {1, 3, 3}, tilted, D) == doctest::Approx(0.03125f).epsilon(1e-6));
}

TEST_CASE("bilateral weight of a neighbour surface is the weight of its position and normal") {
    const Surface ref = receiver();
    Surface n = receiver();
    n.position = {0, 2.5f, 9};
    n.normal = {0, 0.8f, 0.6f};
    // ¼ of D = 2 off the plane → 0.75; cos = 0.8 → 0.4096.
    CHECK(bilateralWeight(ref, n, 2.0f) == bilateralWeight(ref, n.position, n.normal, 2.0f));
    CHECK(bilateralWeight(ref, n, 2.0f) == doctest::Approx(0.75f * 0.4096f).epsilon(1e-6));
}

TEST_CASE("reprojection by velocity: the pixel centre plus its motion") {
    const CameraView cam = testCamera();
    Image v(64, 48, {"X", "Y"});
    const Texture still{v};
    // Zero motion: the pixel centre, whatever the cameras say.
    const PreviousPixel p = reprojectPixel(3, 5, {0, 0, -1}, cam.position, &still, cam);
    CHECK(p.u == 3.5);
    CHECK(p.v == 5.5);
    v.plane(0).at(3, 5) = 1.25f;
    v.plane(1).at(3, 5) = -2.0f;
    const Texture moving{v};
    const PreviousPixel q = reprojectPixel(3, 5, {0, 0, -1}, cam.position, &moving, cam);
    CHECK(q.u == 4.75);
    CHECK(q.v == 3.5);
    // From a depth: with velocity bound the depth is not used (a NaN depth changes nothing);
    // without it, the same as reprojecting the surface rebuilt from that depth.
    const PreviousPixel r = reprojectPixelAtDepth(cam, 3, 5, std::nan(""), &moving, cam);
    CHECK(r.u == 4.75);
    CHECK(r.v == 3.5);
    const PreviousPixel s = reprojectPixelAtDepth(cam, 3, 5, 120.0, nullptr, cam);
    const PreviousPixel t =
        reprojectPixel(3, 5, reprojectionOffset(cam, 3, 5, 120.0), cam.position, nullptr, cam);
    CHECK(s.u == t.u);
    CHECK(s.v == t.v);
}

TEST_CASE("reprojection through the previous camera") {
    const CameraView cam = testCamera({10, 20, 30}, {10, 20, 130});
    SUBCASE("the same camera gives the same pixel") {
        for (const auto& [px, py] : {std::pair{0, 0}, {17, 31}, {63, 47}}) {
            const Vec3d offset = cam.translatedFromPixel(px, py, 250.0);
            const PreviousPixel p = reprojectPixel(px, py, offset, cam.position, nullptr, cam);
            CHECK(p.u == doctest::Approx(px + 0.5).epsilon(1e-9));
            CHECK(p.v == doctest::Approx(py + 0.5).epsilon(1e-9));
            CHECK(p.onScreen({64, 48}));
        }
    }
    SUBCASE("a sideways move shifts a point by fx·Δ/z in screen units") {
        // The point on the optical axis at depth 200; last frame's eye 20 units to the right, so
        // there the point sat at view x = −20: screen x = fx·(−20)/200, pixel u = (sx + 1)/2·W.
        CameraView prev = cam;
        prev.position = cam.position + cam.right * 20.0;
        const PreviousPixel p =
            reprojectPixel(32, 24, cam.forward * 200.0, cam.position, nullptr, prev);
        CHECK(p.u == doctest::Approx((cam.fx * -20.0 / 200.0 + 1.0) / 2.0 * 64.0));
        CHECK(p.v == doctest::Approx(24.0));
    }
    SUBCASE("a point behind the previous camera is off screen") {
        // Last frame's eye stood 300 units further along the view: the surface at depth 250 was
        // behind it, although the projection's divide would put it near the screen centre.
        CameraView prev = cam;
        prev.position = cam.position + cam.forward * 300.0;
        const Vec3d offset = cam.translatedFromPixel(40, 20, 250.0);
        const PreviousPixel p = reprojectPixel(40, 20, offset, cam.position, nullptr, prev);
        CHECK_FALSE(p.onScreen({64, 48}));
        CHECK_FALSE(p.onScreen({1 << 20, 1 << 20}));
    }
}

TEST_CASE("sky reprojects by rotation only") {
    const CameraView cam = testCamera();
    const double inf = std::numeric_limits<double>::infinity();
    const Vec3d sky = reprojectionOffset(cam, 12, 9, inf);
    // A far point along the pixel's own ray.
    const Vec3d dir = cam.rayDirection(12, 9);
    CHECK(dot(normalize(sky), dir) == doctest::Approx(1.0).epsilon(1e-12));
    CHECK(length(sky) > 1e11);
    // A surface reprojects its own position.
    const Vec3d wall = reprojectionOffset(cam, 12, 9, 250.0);
    CHECK(length(wall - cam.translatedFromPixel(12, 9, 250.0)) == 0.0);
    // Moving the eye leaves the sky where it was; turning it moves the sky.
    CameraView moved = cam;
    moved.position = cam.position + Vec3d{300, -50, 1000};
    const PreviousPixel still = reprojectPixel(12, 9, sky, cam.position, nullptr, moved);
    CHECK(still.u == doctest::Approx(12.5).epsilon(1e-6));
    CHECK(still.v == doctest::Approx(9.5).epsilon(1e-6));
    const CameraView turned = testCamera({0, 0, 0}, {10, 0, 100});
    const PreviousPixel swung = reprojectPixel(12, 9, sky, cam.position, nullptr, turned);
    CHECK(std::fabs(swung.u - 12.5) > 1.0);
}

TEST_CASE("on screen means inside [0, W) × [0, H) in continuous pixels") {
    CHECK(PreviousPixel{0.0, 0.0}.onScreen({4, 3}));
    CHECK(PreviousPixel{3.999, 2.999}.onScreen({4, 3}));
    CHECK_FALSE(PreviousPixel{4.0, 1.0}.onScreen({4, 3}));
    CHECK_FALSE(PreviousPixel{1.0, 3.0}.onScreen({4, 3}));
    CHECK_FALSE(PreviousPixel{-0.001, 1.0}.onScreen({4, 3}));
    CHECK_FALSE(PreviousPixel{}.onScreen({4, 3}));
}

TEST_CASE("pixel surface: camera-relative position, world normal and pixel world radius") {
    const CameraView cam = testCamera({5, 6, 7}, {5, 6, 107});
    const FlatGBuffer g({0, 3, 4});  // stored length 5
    const Surface s = pixelSurface(cam, g.inputs(), 20, 10, 1.0f, NormalRead::Normalised);
    REQUIRE(s.valid);
    const Vec3d p = cam.translatedFromPixel(20, 10, 250.0);
    CHECK(s.position.x == float(p.x));
    CHECK(s.position.y == float(p.y));
    CHECK(s.position.z == float(p.z));
    CHECK(s.position.z == doctest::Approx(250.0f));  // looking along +z from the eye
    CHECK(s.normal.y == doctest::Approx(0.6f));
    CHECK(s.normal.z == doctest::Approx(0.8f));
    // The radius is CameraView's pixel world radius, tan(½ horizontal FOV)/W × depth.
    CHECK(s.radius == float(cam.pixelRadiusAtDepth(250.0)));
    CHECK(s.radius == doctest::Approx(250.0 / (cam.fx * 64.0)));
    // A half-resolution texel stands for two pixels across.
    CHECK(pixelSurface(cam, g.inputs(), 20, 10, 2.0f, NormalRead::Normalised).radius ==
          2.0f * s.radius);
    // As stored: the GBuffer's value untouched.
    const Surface raw = pixelSurface(cam, g.inputs(), 20, 10, 1.0f, NormalRead::AsStored);
    CHECK(raw.normal.y == 3.0f);
    CHECK(raw.normal.z == 4.0f);
}

TEST_CASE("sky and unlit pixels have no surface") {
    const CameraView cam = testCamera();
    FlatGBuffer g({0, 1, 0});
    g.depth.at(1, 1) = std::numeric_limits<float>::infinity();
    g.shadingModel.at(2, 1) = float(kUnlit);
    CHECK_FALSE(pixelSurface(cam, g.inputs(), 1, 1, 1.0f, NormalRead::AsStored).valid);
    CHECK_FALSE(pixelSurface(cam, g.inputs(), 2, 1, 1.0f, NormalRead::AsStored).valid);
    CHECK(pixelSurface(cam, g.inputs(), 3, 1, 1.0f, NormalRead::AsStored).valid);
}

TEST_CASE("a half-resolution surface grid reads the top-left pixel of each 2×2 block") {
    const CameraView cam = CameraView::lookAt({0, 0, 0}, {0, 0, 100}, {0, 1, 0}, 60.0, 5, 3, 10.0);
    Plane depth(5, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            depth.at(x, y) = 100.0f + float(10 * x + y);
    Image normal(5, 3, {"X", "Y", "Z"});
    normal.plane(2) = Plane(5, 3, -1.0f);
    const Plane models(5, 3, float(kDefaultLit));
    const SurfaceInputs in{depth, normal, models};
    const SurfaceGrid grid(cam, in, {3, 2}, 2, NormalRead::Normalised);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) {
            // 5×3 → 3×2: texel 2 of a row stands for pixel 4, row 1 for pixel row 2.
            const int px = std::min(2 * x, 4), py = std::min(2 * y, 2);
            const Surface& s = grid.at(x, y);
            REQUIRE(s.valid);
            CHECK(s.position.z == doctest::Approx(depth.at(px, py)));
            CHECK(s.radius == float(cam.pixelRadiusAtDepth(depth.at(px, py))) * 2.0f);
            CHECK(s.normal.z == -1.0f);
        }
}

TEST_CASE("GBuffer ports: one name, channels and capture buffer each") {
    const PortSpec depth = gbuffer::depthInput();
    CHECK(depth.name == "depth");
    CHECK(depth.channels == std::vector<std::string>{"Z"});
    CHECK(depth.captureDefault == "SceneDepth");
    CHECK(depth.doc == "linear view depth");
    CHECK_FALSE(depth.optional);
    CHECK(gbuffer::depthInput("sky pixels are left out", true).optional);
    const PortSpec normal = gbuffer::normalInput();
    CHECK(normal.channels == std::vector<std::string>{"X", "Y", "Z"});
    CHECK(normal.captureDefault == "WorldNormal");
    const PortSpec velocity = gbuffer::velocityInput("motion");
    CHECK(velocity.optional);
    CHECK(velocity.captureDefault.empty());
    CHECK(gbuffer::baseColorInput().kind == PortKind::Color);
    CHECK(gbuffer::shadingModelInput("id").kind == PortKind::Data);

    Image n(2, 2, {"X", "Y", "Z"});
    n.plane(0).at(1, 0) = 0.25f;
    n.plane(1).at(1, 0) = -2.0f;
    n.plane(2).at(1, 0) = 7.0f;
    const Vec3f v = gbuffer::worldNormalAt(n, 1, 0);
    CHECK(v.x == 0.25f);
    CHECK(v.y == -2.0f);  // as stored, not normalised
    CHECK(v.z == 7.0f);
}

}  // namespace fp
