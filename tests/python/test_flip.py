"""FLIP (metrics/Flip.cpp) against the papers' formulas written again here in float64 numpy, with
the full 2D filters as the papers give them (the library filters separably, in float32): LDR-FLIP
(Andersson et al. 2020) and HDR-FLIP (Andersson et al. 2021), through framepass.compare on arrays
and on files. Every constant is taken from the papers, not from the library."""
import os
import subprocess

import numpy as np
import pytest

import framepass as fp

FRAMEPASS = os.environ["FRAMEPASS"]
SCRATCH = os.path.join(os.path.abspath(os.environ["FP_SCRATCH"]), "python-flip")
PPD = 0.7 * 3840 / 0.7 * np.pi / 180  # a 0.7 m wide 4K monitor seen from 0.7 m

# sRGB primaries and D65 white (the exact fractions of the sRGB standard).
RGB2XYZ = np.array([[10135552 / 24577794, 8788810 / 24577794, 4435075 / 24577794],
                    [2613072 / 12288897, 8788810 / 12288897, 887015 / 12288897],
                    [1425312 / 73733382, 8788810 / 73733382, 70074185 / 73733382]])
WHITE = RGB2XYZ.sum(axis=1)


def srgb2lin(c):
    return np.where(c > 0.04045, ((c + 0.055) / 1.055) ** 2.4, c / 12.92)


def lin2srgb(c):
    return np.where(c > 0.0031308, 1.055 * np.maximum(c, 0) ** (1 / 2.4) - 0.055, 12.92 * c)


def to_ycxcz(lin):  # (H, W, 3) linear RGB
    xyz = lin @ RGB2XYZ.T / WHITE
    return np.stack([116 * xyz[..., 1] - 16, 500 * (xyz[..., 0] - xyz[..., 1]),
                     200 * (xyz[..., 1] - xyz[..., 2])], -1)


def from_ycxcz(o):
    y = (o[..., 0] + 16) / 116
    xyz = np.stack([y + o[..., 1] / 500, y, y - o[..., 2] / 200], -1) * WHITE
    return xyz @ np.linalg.inv(RGB2XYZ).T


def hunt_lab(lin):
    t = lin @ RGB2XYZ.T / WHITE
    d = 6 / 29
    f = np.where(t > d ** 3, np.cbrt(t), t / (3 * d * d) + 4 / 29)
    l = 116 * f[..., 1] - 16
    return np.stack([l, 0.01 * l * 500 * (f[..., 0] - f[..., 1]), 0.01 * l * 200 * (f[..., 1] - f[..., 2])], -1)


def hyab(a, b):
    d = a - b
    return np.abs(d[..., 0]) + np.hypot(d[..., 1], d[..., 2])


def filter2d(img, k):
    """Correlation of a (H, W) image with a (2r+1)² kernel, the border replicated."""
    r = k.shape[0] // 2
    p = np.pad(img, r, mode="edge")
    h, w = img.shape
    out = np.zeros_like(img)
    for dy in range(2 * r + 1):
        for dx in range(2 * r + 1):
            out += k[dy, dx] * p[dy:dy + h, dx:dx + w]
    return out


def csf(a1, b1, a2, b2):
    r = int(np.ceil(3 * np.sqrt(0.04 / (2 * np.pi ** 2)) * PPD))
    x, y = np.meshgrid(np.arange(-r, r + 1), np.arange(-r, r + 1))
    z = (x / PPD) ** 2 + (y / PPD) ** 2
    s = a1 * np.sqrt(np.pi / b1) * np.exp(-np.pi ** 2 * z / b1) + a2 * np.sqrt(np.pi / b2) * np.exp(-np.pi ** 2 * z / b2)
    return s / s.sum()


def features(y, points):
    sd = 0.5 * 0.082 * PPD
    r = int(np.ceil(3 * sd))
    x, yy = np.meshgrid(np.arange(-r, r + 1), np.arange(-r, r + 1))
    g = np.exp(-(x ** 2 + yy ** 2) / (2 * sd * sd))
    k = (x ** 2 / sd ** 2 - 1) * g if points else -x * g
    k = np.where(k < 0, k / -k[k < 0].sum(), k / k[k > 0].sum())
    return np.hypot(filter2d(y, k), filter2d(y, k.T))


def ldr_flip(ref, test):  # (H, W, 3) sRGB in [0, 1]
    filters = [csf(1, 0.0047, 0, 1e-5), csf(1, 0.0053, 0, 1e-5), csf(34.1, 0.04, 13.5, 0.025)]
    prepared = []
    for img in (ref, test):
        o = to_ycxcz(srgb2lin(img))
        filtered = np.stack([filter2d(o[..., c], filters[c]) for c in range(3)], -1)
        lab = hunt_lab(np.clip(from_ycxcz(filtered), 0, 1))
        lum = (o[..., 0] + 16) / 116
        prepared.append((lab, features(lum, False), features(lum, True)))
    (lr, er, pr), (lt, et, pt_) = prepared
    cmax = hyab(hunt_lab(np.array([0.0, 1, 0])), hunt_lab(np.array([0.0, 0, 1]))) ** 0.7
    de = hyab(lr, lt) ** 0.7
    colour = np.where(de < 0.4 * cmax, 0.95 / (0.4 * cmax) * de, 0.95 + (de - 0.4 * cmax) / (0.6 * cmax) * 0.05)
    feat = (np.maximum(np.abs(er - et), np.abs(pr - pt_)) / np.sqrt(2)) ** 0.5
    return colour ** (1 - feat)


K = [0.6 * 0.6 * 2.51, 0.6 * 0.03, 0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14]  # ACES (Narkowicz), 0.6 folded in


def aces(x):
    return np.clip((K[0] * x * x + K[1] * x + K[2]) / (K[3] * x * x + K[4] * x + K[5]), 0, 1)


def aces_inverse(t):
    c0 = (K[1] - K[4] * t) / (K[0] - K[3] * t)
    c1 = (K[2] - K[5] * t) / (K[0] - K[3] * t)
    return -0.5 * c0 + np.sqrt(0.25 * c0 * c0 - c1)


def hdr_flip(ref, test):
    lum = ref @ np.array([0.2126, 0.7152, 0.0722])
    start = np.log2(aces_inverse(0.85) / lum.max())
    stop = np.log2(aces_inverse(0.85) / np.median(lum))
    n = max(2, int(np.ceil(stop - start)))
    errors = [ldr_flip(lin2srgb(aces(np.maximum(ref, 0) * 2 ** e)), lin2srgb(aces(np.maximum(test, 0) * 2 ** e)))
              for e in np.linspace(start, stop, n)]
    return np.max(errors, axis=0), (start, stop, n)


def scene(h=40, w=48, seed=1):
    """A lit-looking picture: a gradient, a bright square, an edge and some noise."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:h, 0:w] / max(h, w)
    img = np.stack([0.2 + 0.6 * x, 0.3 + 0.4 * y, 0.5 - 0.3 * x * y], -1)
    img[10:22, 14:30] = [1.8, 1.5, 0.9]
    img[:, 36:] *= 0.25
    return img + 0.03 * rng.standard_normal(img.shape)


# float32 filtering in the library against float64 here: the means agree to within 1e-7 (measured;
# the bound leaves room for another compiler's rounding where an error near 0 is raised to 0.7).
TOL = 1e-5


def test_ldr_flip_matches_the_paper():
    ref = np.clip(scene() / 2, 0, 1)
    test = np.clip(ref + 0.08 * np.sin(np.arange(48) / 2.0)[None, :, None], 0, 1)
    want = ldr_flip(ref, test).mean()
    got = fp.compare(test.astype(np.float32), ref.astype(np.float32), flip="ldr")
    assert abs(got["flip"] - want) < TOL, (got["flip"], want)
    assert got["flipSettings"]["mode"] == "ldr" and 0.05 < want < 0.9  # a real, visible difference


def test_hdr_flip_matches_the_paper_with_its_exposures():
    ref = np.maximum(scene(seed=2), 0)
    test = ref * 1.15 + 0.02
    want, (start, stop, n) = hdr_flip(ref, test)
    got = fp.compare(test.astype(np.float32), ref.astype(np.float32))  # arrays: HDR by default
    s = got["flipSettings"]
    assert s["mode"] == "hdr" and s["exposures"] == n
    assert abs(s["startExposure"] - start) < 1e-5 and abs(s["stopExposure"] - stop) < 1e-5
    assert abs(got["flip"] - want.mean()) < TOL, (got["flip"], want.mean())


def test_flip_is_zero_for_equal_images_grey_for_one_channel_and_off_when_asked():
    ref = np.maximum(scene(seed=3), 0).astype(np.float32)
    assert fp.compare(ref, ref)["flip"] == 0.0
    grey = ref[..., 1]
    one = fp.compare(grey * 1.2, grey, flip="hdr")["flip"]
    three = fp.compare(np.repeat(grey[..., None] * 1.2, 3, -1), np.repeat(grey[..., None], 3, -1), flip="hdr")["flip"]
    assert one == pytest.approx(three, abs=1e-7) and one > 0.01
    assert fp.compare(ref * 2, ref, flip="off")["flip"] is None
    assert fp.compare(ref[..., :2] * 2, ref[..., :2])["flip"] is None  # two channels: no colour
    with pytest.raises(fp.ConfigError, match="auto, hdr, ldr or off"):
        fp.compare(ref, ref, flip="perceptual")
    assert fp.compare(ref * 2, ref, metric="flip") > 0.05


def test_files_give_the_arrays_figure_and_the_heat_map_holds_the_per_pixel_error(tmp_path):
    ref = np.maximum(scene(seed=4), 0).astype(np.float32)
    test = (ref * 0.8).astype(np.float32)
    fp.write_exr(str(tmp_path / "ref.exr"), {"Color": ref})
    fp.write_exr(str(tmp_path / "test.exr"), {"Color": test})
    heat = str(tmp_path / "heat.exr")
    got = fp.compare(str(tmp_path / "test.exr"), str(tmp_path / "ref.exr"), layer="Color",
                     masks=["none"], heatmap=heat)
    want, _ = hdr_flip(ref.astype(np.float64), test.astype(np.float64))
    assert got["flip"] == fp.compare(test, ref)["flip"]
    per_pixel = fp.read_exr(heat)["Flip"][..., 0]
    assert np.abs(per_pixel - want).max() < 2e-3 and abs(per_pixel.mean() - got["flip"]) < 1e-6
    cli = subprocess.run([FRAMEPASS, "compare", str(tmp_path / "test.exr"), str(tmp_path / "ref.exr"),
                          "--layer", "Color", "--mask", "none", "--flip", "hdr", "--ppd", "40"],
                         capture_output=True, text=True, check=True).stdout
    assert "FLIP" in cli and "40 pixels per degree" in cli


def test_error_measure_takes_flip_as_compare_does():
    """error_measure's flip parameter: the metric bench, the report and the workbench show, the
    per-pixel map as an output, and the figure compare gives for the same arrays and mask."""
    source = os.environ["FP_SOURCE_DIR"]
    os.makedirs(SCRATCH, exist_ok=True)
    capture = os.path.join(SCRATCH, "cornell.exr")
    subprocess.run([FRAMEPASS, "-q", "capture", os.path.join(source, "examples/cornell/scene.json"),
                    "-o", capture, "--width", "64", "--height", "48", "--truth", "--truth-spp", "4",
                    "--light-samples", "2"], check=True)
    s = fp.Session(os.path.join(source, "examples/cornell/bench.json"), capture=capture)
    s.set("ssgi_vs_full.flip", "hdr")
    out = s.run(outputs=["ssgi_vs_full.flip", "ssgi_denoise.diffuse", "Truth.DiffuseIndirectFull", "SceneDepth"])
    metrics = next(p["metrics"] for p in s.report()["passes"] if p["name"] == "ssgi_vs_full")
    mask = np.isfinite(out["SceneDepth"][..., 0]).astype(np.float32)  # the measure's sky mask
    # The pass's parameters are float32: its observer is PPD rounded to one.
    ppd = float(np.float32(PPD))
    want = fp.compare(out["ssgi_denoise.diffuse"], out["Truth.DiffuseIndirectFull"], mask=mask,
                      flip="hdr", ppd=ppd)
    assert metrics["flip"] == want["flip"] and 0 < metrics["flip"] < 1
    per_pixel = out["ssgi_vs_full.flip"][..., 0]
    assert abs(per_pixel[mask > 0].mean() - metrics["flip"]) < 1e-6
    with pytest.raises(fp.SettingValueError, match="hdr"):
        s.set("ssgi_vs_full.flip", "perceptual")
