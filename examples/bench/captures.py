"""What the bench scripts share: the Cornell box captured once per size into out/bench/."""
import json
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


def workbench_config(framepass, out, width, height, name):
    """examples/cornell/bench.json on a Cornell capture with truth at width × height, written as
    OUT/NAME_WxH.json: what the workbench benchmarks serve."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    with open(os.path.join(root, "examples/cornell/bench.json")) as f:
        j = json.load(f)
    j["capture"] = cornell_capture(framepass, out, width, height, truth_spp=16)
    config = os.path.join(out, f"{name}_{width}x{height}.json")
    with open(config, "w") as f:
        json.dump(j, f)
    return config
