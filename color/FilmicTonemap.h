#pragma once
// Unreal Engine 4.27's filmic tonemapper (the "ACES-fitted" film curve every Unreal viewport shows
// by default): scene-linear Rec.709 in, display-linear Rec.709 in [0, 1] out, before the sRGB
// encoding. The steps, as docs/color.md writes them out: into ACES AP0 (D65 → D60, Bradford);
// ACES 1.0's RRT "glow" and "red modifier"; into AP1 (ACEScg); a 4 % pre-desaturation; the film
// curve — a logistic toe and shoulder joined by a straight segment of slope FilmSlope in log10,
// placed so that 0.18 in gives 0.18 out — per channel; a 7 % post-desaturation; back to Rec.709.
// Unreal's defaults: slope 0.88, toe 0.55, shoulder 0.26, black clip 0, white clip 0.04.
// Both backends run this code (the display pass's CPU tiles and its CUDA kernel).
#include "foundation/HostDevice.h"

#include <cmath>

namespace fp::color {

/// The film curve's parameters (Unreal's post-process Film* settings).
struct FilmParams {
    float slope = 0.88f, toe = 0.55f, shoulder = 0.26f, blackClip = 0.0f, whiteClip = 0.04f;
};

namespace filmic {

/// A 3 × 3 matrix, row-major. Returned by functions, not held in namespace constants, so that
/// the device code may read them too.
struct Matrix3 {
    float m[9];
};

// Rec.709/sRGB (D65) ↔ AP1 (D60, Bradford adaptation), AP0 ↔ AP1: from the primaries and white
// points (docs/color.md gives them; tests/python/test_filmic.py derives the matrices again).
FP_HD constexpr Matrix3 rec709ToAp1() {
    return {{0.6130974024f, 0.3395231462f, 0.0473794514f,
             0.0701937225f, 0.9163538791f, 0.0134523985f,
             0.0206155929f, 0.1095697729f, 0.8698146342f}};
}
FP_HD constexpr Matrix3 ap1ToRec709() {
    return {{1.7050509927f,  -0.6217921207f, -0.0832588720f,
             -0.1302564175f, 1.1408047366f,  -0.0105483191f,
             -0.0240033568f, -0.1289689761f, 1.1529723329f}};
}
FP_HD constexpr Matrix3 ap0ToAp1() {
    return {{1.4514393161f,  -0.2365107469f, -0.2149285693f,
             -0.0765537734f, 1.1762296998f,  -0.0996759264f,
             0.0083161484f,  -0.0060324498f, 0.9977163014f}};
}
FP_HD constexpr Matrix3 ap1ToAp0() {
    return {{0.6954522414f, 0.1406786965f, 0.1638690622f,
             0.0447945634f, 0.8596711185f, 0.0955343182f,
             -0.0055258826f, 0.0040252103f, 1.0015006723f}};
}
/// AP1's luminance (its weights are the Y row of AP1 → XYZ).
FP_HD inline float ap1Luma(const float* c) {
    return 0.2722287168f * c[0] + 0.6740817658f * c[1] + 0.0536895174f * c[2];
}

FP_HD inline void multiply(const Matrix3& a, const float* in, float* out) {
    for (int r = 0; r < 3; ++r)
        out[r] = a.m[3 * r] * in[0] + a.m[3 * r + 1] * in[1] + a.m[3 * r + 2] * in[2];
}

// ACES 1.0 RRT helpers.
FP_HD inline float saturation(const float* rgb) {
    const float lo = fminf(rgb[0], fminf(rgb[1], rgb[2]));
    const float hi = fmaxf(rgb[0], fmaxf(rgb[1], rgb[2]));
    return (fmaxf(hi, 1e-10f) - fmaxf(lo, 1e-10f)) / fmaxf(hi, 1e-2f);
}
/// Luminance-like "yc": the mean of the channels plus 1.75 × the chroma, over 3.
FP_HD inline float yc(const float* rgb) {
    const float r = rgb[0], g = rgb[1], b = rgb[2];
    const float chroma = sqrtf(fmaxf(b * (b - g) + g * (g - r) + r * (r - b), 0.0f));
    return (b + g + r + 1.75f * chroma) / 3.0f;
}
FP_HD inline float sigmoidShaper(float x) {
    const float t = fmaxf(1.0f - fabsf(x / 2.0f), 0.0f);
    const float y = 1.0f + (x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f)) * (1.0f - t * t);
    return y / 2.0f;
}
FP_HD inline float glowForward(float ycIn, float glowGain, float glowMid) {
    if (ycIn <= 2.0f / 3.0f * glowMid) return glowGain;
    if (ycIn >= 2.0f * glowMid) return 0.0f;
    return glowGain * (glowMid / ycIn - 0.5f);
}
/// Hue in degrees, [0, 360); 0 for a grey.
FP_HD inline float hue(const float* rgb) {
    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) return 0.0f;
    float h = 57.29577951308232f * atan2f(1.7320508075688772f * (rgb[1] - rgb[2]),
                                          2.0f * rgb[0] - rgb[1] - rgb[2]);
    return h < 0.0f ? h + 360.0f : h;
}
FP_HD inline float centeredHue(float h, float centre) {
    float c = h - centre;
    if (c < -180.0f) c += 360.0f;
    else if (c > 180.0f) c -= 360.0f;
    return c;
}
FP_HD inline float smoothstep01(float x) {
    const float t = fminf(fmaxf(x, 0.0f), 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

/// The film curve on one AP1 channel (Unreal's FilmToneMap after the desaturation).
FP_HD inline float curve(const FilmParams& p, float v) {
    const float toeScale = 1.0f + p.blackClip - p.toe;
    const float shoulderScale = 1.0f + p.whiteClip - p.shoulder;
    const float inMatch = 0.18f, outMatch = 0.18f;
    float toeMatch;
    if (p.toe > 0.8f) {  // 0.18 on the straight segment
        toeMatch = (1.0f - p.toe - outMatch) / p.slope + log10f(inMatch);
    } else {  // 0.18 on the toe: solve the toe for inMatch → outMatch
        const float bt = (outMatch + p.blackClip) / toeScale - 1.0f;
        toeMatch = log10f(inMatch) - 0.5f * logf((1.0f + bt) / (1.0f - bt)) * (toeScale / p.slope);
    }
    const float straightMatch = (1.0f - p.toe) / p.slope - toeMatch;
    const float shoulderMatch = p.shoulder / p.slope - straightMatch;

    // Unreal evaluates the curve only at its colour table's entries, never at 0 (log10 0 would
    // make the blend below 0 × ∞): the same floor here.
    const float logColor = log10f(fmaxf(v, 1e-10f));
    const float straight = p.slope * (logColor + straightMatch);
    float toeColor = -p.blackClip +
                     (2.0f * toeScale) / (1.0f + expf((-2.0f * p.slope / toeScale) * (logColor - toeMatch)));
    float shoulderColor = (1.0f + p.whiteClip) -
                          (2.0f * shoulderScale) /
                              (1.0f + expf((2.0f * p.slope / shoulderScale) * (logColor - shoulderMatch)));
    toeColor = logColor < toeMatch ? toeColor : straight;
    shoulderColor = logColor > shoulderMatch ? shoulderColor : straight;
    float t = fminf(fmaxf((logColor - toeMatch) / (shoulderMatch - toeMatch), 0.0f), 1.0f);
    t = shoulderMatch < toeMatch ? 1.0f - t : t;
    t = (3.0f - 2.0f * t) * t * t;
    return toeColor + t * (shoulderColor - toeColor);
}

}  // namespace filmic

/// UE 4.27's FilmToneMap on a scene-linear Rec.709 colour: display-linear Rec.709, ≥ 0 (values
/// above 1 are possible with a white clip; the display clamps). Evaluated per pixel, where Unreal
/// bakes it into a 32³ table; Unreal's blue correction and gamut expansion are not applied.
FP_HD inline void ue4FilmicTonemap(const FilmParams& p, const float* rec709, float* out) {
    using namespace filmic;
    float ap1[3], ap0[3];
    multiply(rec709ToAp1(), rec709, ap1);
    multiply(ap1ToAp0(), ap1, ap0);
    // Glow: lifts dark saturated colours (ACES 1.0 RRT).
    const float sat = saturation(ap0);
    const float s = sigmoidShaper((sat - 0.4f) / 0.2f);
    const float glow = 1.0f + glowForward(yc(ap0), 0.05f * s, 0.08f);
    for (int c = 0; c < 3; ++c) ap0[c] *= glow;
    // Red modifier: pulls saturated reds' red channel toward a pivot.
    const float centred = centeredHue(hue(ap0), 0.0f);
    const float w = smoothstep01(1.0f - fabsf(2.0f * centred / 135.0f));
    ap0[0] += w * w * sat * (0.03f - ap0[0]) * (1.0f - 0.82f);
    // The working colour in AP1, no negatives, desaturated 4 %.
    multiply(ap0ToAp1(), ap0, ap1);
    for (int c = 0; c < 3; ++c) ap1[c] = fmaxf(ap1[c], 0.0f);
    float luma = ap1Luma(ap1);
    for (int c = 0; c < 3; ++c) ap1[c] = luma + 0.96f * (ap1[c] - luma);
    float toned[3];
    for (int c = 0; c < 3; ++c) toned[c] = curve(p, ap1[c]);
    // Post-desaturation 7 %, then positive AP1 back to Rec.709.
    luma = ap1Luma(toned);
    for (int c = 0; c < 3; ++c) toned[c] = fmaxf(luma + 0.93f * (toned[c] - luma), 0.0f);
    multiply(ap1ToRec709(), toned, out);
    for (int c = 0; c < 3; ++c) out[c] = fmaxf(out[c], 0.0f);
}

/// The sRGB encoding (IEC 61966-2-1) of a display-linear value in [0, 1].
FP_HD inline float srgbEncode(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}

}  // namespace fp::color
