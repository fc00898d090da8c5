// The light-attenuation encoding shadow passes write and deferred lighting reads.
#include "shading/LightAttenuation.h"

#include <doctest/doctest.h>

#include <cmath>

namespace fp {

TEST_CASE("light attenuation: √ on write, ² on read, Unreal's channel layout") {
    for (float v = 0.0f; v <= 1.0f; v += 1.0f / 64.0f)
        CHECK(LightAttenuation::decode(LightAttenuation::encode(v)) ==
              doctest::Approx(v).epsilon(1e-6));
    // ShadowFadeFraction = 1 (algorithms §9.4): the stored value is the shadow itself and lights
    // see its square.
    const LightAttenuation dir = LightAttenuation::fromShadow(LightType::Directional, 0.6f, 0.3f);
    CHECK(dir.r == doctest::Approx(0.6f));
    CHECK(dir.g == doctest::Approx(0.3f));
    CHECK(dir.b == 1.0f);  // the whole-scene light leaves the local-light channel alone
    CHECK(dir.surfaceShadow(LightType::Directional) == doctest::Approx(0.36f));
    CHECK(dir.transmissionShadow(LightType::Directional) == doctest::Approx(0.09f));
    const LightAttenuation point = LightAttenuation::fromShadow(LightType::Point, 0.6f, 0.3f);
    CHECK(point.b == doctest::Approx(0.6f));
    CHECK(point.a == doctest::Approx(0.3f));
    CHECK(point.surfaceShadow(LightType::Point) == doctest::Approx(0.36f));
    CHECK(point.transmissionShadow(LightType::Point) == doctest::Approx(0.09f));
}


}  // namespace fp
