"""Unreal 4.27's filmic tonemapper (the display pass's tonemapper "ue4.27-film") against the
published formula, written again here in float64 numpy from Unreal's FilmToneMap and the ACES 1.0
RRT helpers it calls (docs/color.md gives each step), with the colour matrices derived here from
the primaries and white points rather than copied. Greys, saturated colours, darks and highlights,
at Unreal's defaults and with a changed curve.

Tolerance: the library computes in float32 (a 2^-24 relative step) through about thirty operations
and a log10 → exp round trip that the slope does not amplify beyond ×2; after the sRGB encoding
(whose slope is at most 12.92) 2e-5 absolute bounds that with room, and is 200× finer than the
8-bit step the display writes."""
import json
import os

import numpy as np
import pytest

import framepass as fp

D65, D60 = (0.3127, 0.3290), (0.32168, 0.33767)
BRADFORD = np.array([[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]])


def xyz(x, y):
    return np.array([x / y, 1.0, (1 - x - y) / y])


def rgb_to_xyz(primaries, white):
    p = np.stack([xyz(*c) for c in primaries], axis=1)
    return p * np.linalg.solve(p, xyz(*white))


def adapt(src, dst):
    s, d = BRADFORD @ xyz(*src), BRADFORD @ xyz(*dst)
    return np.linalg.inv(BRADFORD) @ np.diag(d / s) @ BRADFORD


REC709 = rgb_to_xyz([(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)], D65)
AP0 = rgb_to_xyz([(0.7347, 0.2653), (0.0, 1.0), (0.0001, -0.0770)], D60)
AP1 = rgb_to_xyz([(0.713, 0.293), (0.165, 0.830), (0.128, 0.044)], D60)
REC709_TO_AP1 = np.linalg.inv(AP1) @ adapt(D65, D60) @ REC709
AP1_TO_AP0 = np.linalg.inv(AP0) @ AP1
AP1_LUMA = AP1[1]


def film_curve(x, slope, toe, shoulder, black, white):
    toe_scale, shoulder_scale = 1 + black - toe, 1 + white - shoulder
    if toe > 0.8:
        toe_match = (1 - toe - 0.18) / slope + np.log10(0.18)
    else:
        bt = (0.18 + black) / toe_scale - 1
        toe_match = np.log10(0.18) - 0.5 * np.log((1 + bt) / (1 - bt)) * (toe_scale / slope)
    straight_match = (1 - toe) / slope - toe_match
    shoulder_match = shoulder / slope - straight_match
    log = np.log10(np.maximum(x, 1e-10))
    straight = slope * (log + straight_match)
    toe_c = -black + 2 * toe_scale / (1 + np.exp(-2 * slope / toe_scale * (log - toe_match)))
    shoulder_c = 1 + white - 2 * shoulder_scale / (1 + np.exp(2 * slope / shoulder_scale * (log - shoulder_match)))
    toe_c = np.where(log < toe_match, toe_c, straight)
    shoulder_c = np.where(log > shoulder_match, shoulder_c, straight)
    t = np.clip((log - toe_match) / (shoulder_match - toe_match), 0, 1)
    t = 1 - t if shoulder_match < toe_match else t
    t = (3 - 2 * t) * t * t
    return toe_c + t * (shoulder_c - toe_c)


def ue4_film(rgb, slope=0.88, toe=0.55, shoulder=0.26, black=0.0, white=0.04):
    """FilmToneMap of one Rec.709 colour, then the sRGB encoding: what the display writes."""
    ap1 = REC709_TO_AP1 @ rgb
    ap0 = AP1_TO_AP0 @ ap1
    lo, hi = ap0.min(), ap0.max()
    sat = (max(hi, 1e-10) - max(lo, 1e-10)) / max(hi, 1e-2)
    r, g, b = ap0
    yc = (r + g + b + 1.75 * np.sqrt(max(b * (b - g) + g * (g - r) + r * (r - b), 0))) / 3
    x = (sat - 0.4) / 0.2
    s = (1 + np.sign(x) * (1 - max(1 - abs(x / 2), 0) ** 2)) / 2
    gain = 0.05 * s
    glow = gain if yc <= 2 / 3 * 0.08 else 0 if yc >= 0.16 else gain * (0.08 / yc - 0.5)
    ap0 = ap0 * (1 + glow)
    r, g, b = ap0
    hue = 0.0 if r == g == b else np.degrees(np.arctan2(np.sqrt(3) * (g - b), 2 * r - g - b)) % 360
    centred = (hue + 180) % 360 - 180
    w = np.clip(1 - abs(2 * centred / 135), 0, 1)
    w = w * w * (3 - 2 * w)
    ap0[0] += w * w * sat * (0.03 - ap0[0]) * (1 - 0.82)
    work = np.maximum(np.linalg.solve(AP1_TO_AP0, ap0), 0)
    luma = AP1_LUMA @ work
    work = luma + 0.96 * (work - luma)
    toned = film_curve(work, slope, toe, shoulder, black, white)
    luma = AP1_LUMA @ toned
    toned = np.maximum(luma + 0.93 * (toned - luma), 0)
    out = np.clip(np.linalg.solve(REC709_TO_AP1, toned), 0, 1)
    return np.clip(np.where(out <= 0.0031308, 12.92 * out, 1.055 * out ** (1 / 2.4) - 0.055), 0, 1)


COLOURS = np.array([
    [0.0, 0.0, 0.0], [0.001, 0.001, 0.001], [0.02, 0.02, 0.02], [0.18, 0.18, 0.18],
    [0.5, 0.5, 0.5], [1.0, 1.0, 1.0], [4.0, 4.0, 4.0], [30.0, 30.0, 30.0],
    [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.04, 0.01, 0.005],
    [0.8, 0.3, 0.1], [0.1, 0.4, 0.9], [2.5, 1.2, 0.2], [0.05, 0.3, 0.05],
], np.float32)


@pytest.fixture(scope="module")
def config(tmp_path_factory):
    folder = tmp_path_factory.mktemp("filmic")
    path = os.path.join(folder, "film.json")
    with open(path, "w") as f:
        json.dump({"version": 1, "capture": "unused.exr",
                   "passes": [{"name": "display", "type": "display",
                               "params": {"tonemapper": "ue4.27-film"}}],
                   "outputs": {"final.png": "display.image"}}, f)
    return path


def shown(config, settings=None):
    capture = fp.Capture.from_arrays({"SceneColor": COLOURS.reshape(4, 4, 3)})
    s = fp.Session(config, capture=capture)
    for name, value in (settings or {}).items():
        s.set(name, value)
    return s.run(outputs=["display.image"])["display.image"].reshape(-1, 3)


@pytest.mark.parametrize("settings, curve", [
    ({}, {}),
    ({"display.exposure": 2.0}, {}),
    ({"display.filmSlope": 0.7, "display.filmToe": 0.3, "display.filmShoulder": 0.5,
      "display.filmBlackClip": 0.01, "display.filmWhiteClip": 0.1},
     {"slope": 0.7, "toe": 0.3, "shoulder": 0.5, "black": 0.01, "white": 0.1}),
    ({"display.filmToe": 0.9}, {"toe": 0.9}),  # the toe's other branch: 0.18 on the straight line
])
def test_the_film_curve_is_unreals_formula(config, settings, curve):
    got = shown(config, settings)
    gain = 2.0 ** settings.get("display.exposure", 0.0)
    want = np.array([ue4_film(c.astype(np.float64) * gain, **curve) for c in COLOURS])
    assert np.abs(got - want).max() <= 2e-5, np.abs(got - want).max()


def test_the_film_curve_keeps_middle_grey_and_orders_greys(config):
    got = shown(config)
    greys = got[:8, 0]
    # 0.18 in, 0.18 out before the encoding (the curve is placed so): sRGB 0.18 = 0.46135.
    assert abs(greys[3] - 0.46135) < 2e-3
    # Black stays black: 0 is read as 1e-10, which the toe maps to ~1e-15, far below 8 bits' step.
    assert np.all(np.diff(greys) > 0) and greys[0] < 1e-9 and greys[-1] <= 1
