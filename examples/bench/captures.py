"""What the bench scripts share: the Cornell box captured once per size into out/bench/."""
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def cornell_capture(framepass, out, width, height, truth_spp=0):
    """out/bench/cornell[_truth]_<W>x<H>.exr, captured on the first call (with truth layers at
    truth_spp samples when > 0) and kept."""
    os.makedirs(out, exist_ok=True)
    exr = os.path.join(out, f"cornell{'_truth' if truth_spp else ''}_{width}x{height}.exr")
    if not os.path.exists(exr):
        print(f"capturing the Cornell box at {width}x{height}{' with truth' if truth_spp else ''} "
              "(once) ...", file=sys.stderr)
        args = [framepass, "-q", "capture", os.path.join(ROOT, "examples/cornell/scene.json"),
                "-o", exr, "--width", str(width), "--height", str(height)]
        if truth_spp:
            args += ["--truth", "--truth-spp", str(truth_spp)]
        subprocess.run(args, check=True)
    return exr
