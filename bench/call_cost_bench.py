#!/usr/bin/env python3
"""The time a GL call costs the calling thread with glcast: bench/call_cost.c (20,000
immediate-mode calls a frame into an 8x8 window) natively, under the shim with no consumer,
capturing to a file, and publishing on ipc:// with the journal and no slave; its thread CPU time
per call, interleaved runs, medians.
Each SHIM=PATH argument adds a column for another build of the shim (an A/B of a change).

    bench/call_cost_bench.py BUILD_DIR [NAME=SHIM.so ...] [--repeats N]
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("shims", nargs="*", help="NAME=PATH of another libglcast.so")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="glcast-call-cost-")
    program = os.path.join(tmp, "call_cost")
    subprocess.run(["gcc", "-O2", "-o", program, os.path.join(HERE, "call_cost.c"), "-lGL", "-lX11"], check=True)
    shims = {"this build": os.path.join(os.path.abspath(a.build), "libglcast.so")}
    shims.update(s.split("=", 1) for s in a.shims)
    modes = {"native": {}}
    for name, shim in shims.items():
        # interposition alone: the shim's entry points with nothing recording (the floor of any shim)
        modes[f"no consumer ({name})"] = {"LD_PRELOAD": shim}
        modes[f"capture ({name})"] = {"LD_PRELOAD": shim, "GLCAST_CAPTURE": os.path.join(tmp, "c.glcs")}
        stream = f"ipc://{tmp}/s"
        modes[f"publish ({name})"] = {"LD_PRELOAD": shim, "GLCAST_PUBLISH": stream,
                                      "GLCAST_JOURNAL_ENDPOINT": stream + "-journal"}
    results = {m: [] for m in modes}
    with Xvfb():
        for _ in range(a.repeats):
            for mode, env in modes.items():
                r = subprocess.run([program, "100", "20000"], env=dict(os.environ, **env), capture_output=True,
                                   text=True, timeout=300)
                if r.returncode != 0 or "ns_per_call" not in r.stdout:
                    sys.exit(f"{mode}: {r.stderr[-500:]}")
                results[mode].append(float(r.stdout.split()[2]))
    native = statistics.median(results["native"])
    print("| mode | ns per call (median) | over native | runs |")
    print("|---|---|---|---|")
    for mode, v in results.items():
        m = statistics.median(v)
        print(f"| {mode} | {m:.1f} | {m - native:+.1f} | {', '.join(f'{x:.0f}' for x in v)} |")


if __name__ == "__main__":
    main()
