#pragma once
// Unreal's light-attenuation buffer (algorithms §9.5): RGBA = whole-scene (directional) shadow, its
// subsurface term, non-whole-scene (local light) shadow, its subsurface term. Values are stored as
// √value and read back squared, an 8-bit-friendly gamma. The ray-traced shadow pass writes its
// shadow with ShadowFadeFraction = 1, i.e. FadedShadow = Shadow², so the stored value is Shadow and
// the lights see Shadow² (algorithms §9.4).
#include "foundation/HostDevice.h"
#include "foundation/Image.h"
#include "foundation/PlaneView.h"
#include "foundation/Math.h"
#include "foundation/Scene.h"

#include <algorithm>
#include <cmath>

namespace fp {

struct LightAttenuation {
    float r = 1, g = 1, b = 1, a = 1;  //!< encoded (√) channel values

    FP_HD static float encode(float value) { return std::sqrt(saturate(value)); }
    FP_HD static float decode(float stored) { return stored * stored; }

    /// What the RT shadow pass writes for one light: directional lights fill the whole-scene
    /// channels and leave B at 1, every other light writes its shadow into both pairs.
    FP_HD static LightAttenuation fromShadow(LightType type, float shadow, float subsurface) {
        const float s = encode(shadow * shadow), t = encode(subsurface * subsurface);
        if (type == LightType::Directional) return {s, t, 1.0f, t};
        return {s, t, s, t};
    }

    /// The buffer's four planes at one pixel.
    static LightAttenuation load(const Image& image, int x, int y) {
        return {image.plane(0).at(x, y), image.plane(1).at(x, y), image.plane(2).at(x, y),
                image.plane(3).at(x, y)};
    }
    /// The same from views of the planes (per-pixel code on either backend).
    FP_HD static LightAttenuation load(const PlaneView (&p)[4], int x, int y) {
        return {p[0].at(x, y), p[1].at(x, y), p[2].at(x, y), p[3].at(x, y)};
    }
    void store(Image& image, int x, int y) const {
        image.plane(0).at(x, y) = r;
        image.plane(1).at(x, y) = g;
        image.plane(2).at(x, y) = b;
        image.plane(3).at(x, y) = a;
    }

    /// GetShadowTerms (algorithms §9.5) without static shadowing or distance fade: the opaque
    /// surface shadow and the transmission shadow a light of `type` applies.
    FP_HD float surfaceShadow(LightType type) const {
        return type == LightType::Directional ? decode(r) * decode(b) : decode(b);
    }
    FP_HD float transmissionShadow(LightType type) const {
        const float dg = decode(g), da = decode(a);
        return type == LightType::Directional ? (da < dg ? da : dg) * decode(b) : da;  // std::min
    }
};

}  // namespace fp
