#!/usr/bin/env python3
"""Capture overhead and size: frames per second of each program natively, under the shim with
no consumer, capturing to a file, and under `apitrace trace`; bytes per frame of our capture
and of apitrace's trace. Ratios come from one run with the configurations interleaved, because
the machines are noisy. Writes a markdown table to stdout.

    bench/capture_bench.py BUILD_DIR [--frames N] [--repeats R]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def programs(build, frames):
    apps = os.path.join(build, "tests", "apps")
    return {
        "glxgears": ["glxgears"],
        "ff_scene": [os.path.join(apps, "ff_scene"), "--frames", str(frames + 50)],
        "core_scene": [os.path.join(apps, "core_scene"), "--frames", str(frames + 50)],
        "xscreensaver gears (EGL)": ["/usr/libexec/xscreensaver/gears", "-window", "-delay", "0"],
        "xscreensaver glmatrix (EGL)": ["/usr/libexec/xscreensaver/glmatrix", "-window", "-delay", "0"],
    }


def run(cmd, env, frames):
    env = dict(os.environ, FRAME_COUNTER_EXIT=str(frames), FRAME_COUNTER_SKIP="10", **env)
    r = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    m = re.search(r"frame_counter: (\d+) frames in ([\d.]+) s", r.stderr)
    if not m:
        raise RuntimeError(f"{cmd}: no frame count: {r.stderr[-1500:]}")
    return int(m.group(1)) / float(m.group(2))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    shim = os.path.join(build, "libglcast.so")
    glcast = os.path.join(build, "glcast")
    tmp = tempfile.mkdtemp(prefix="glcast-bench-")
    counter = os.path.join(tmp, "frame_counter.so")
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", counter, os.path.join(HERE, "frame_counter.c"), "-ldl"],
                   check=True)
    rows = []
    with Xvfb():
        for name, cmd in programs(build, a.frames).items():
            if not os.path.exists(cmd[0]) and "/" in cmd[0]:
                print(f"{name}: {cmd[0]} not built, skipped", file=sys.stderr)
                continue
            capture = os.path.join(tmp, "c.glcs")
            trace = os.path.join(tmp, "t.trace")
            configs = {
                "native": (cmd, {"LD_PRELOAD": counter}),
                "shim": (cmd, {"LD_PRELOAD": f"{counter}:{shim}"}),
                "capture": (cmd, {"LD_PRELOAD": f"{counter}:{shim}", "GLCAST_CAPTURE": capture}),
                "apitrace": (["apitrace", "trace", "-o", trace, "--"] + cmd, {"LD_PRELOAD": counter}),
            }
            fps = {k: [] for k in configs}
            for _ in range(a.repeats):
                for k, (c, env) in configs.items():
                    fps[k].append(run(c, env, a.frames))
            med = {k: statistics.median(v) for k, v in fps.items()}
            # sizes: complete files of exactly `frames` frames
            size_frames = 200
            subprocess.run(cmd, env=dict(os.environ, LD_PRELOAD=shim, GLCAST_CAPTURE=capture,
                                         GLCAST_FRAMES=str(size_frames), GLCAST_EXIT_AFTER_FRAMES="1"),
                           capture_output=True, timeout=600, check=True)
            ours = os.path.getsize(capture) / size_frames
            subprocess.run(["apitrace", "trace", "-o", trace, "--"] + cmd,
                           env=dict(os.environ, LD_PRELOAD=counter, FRAME_COUNTER_EXIT=str(size_frames),
                                    FRAME_COUNTER_SKIP="1"), capture_output=True, timeout=600)
            theirs = os.path.getsize(trace) / size_frames
            rows.append((name, med, ours, theirs))
            print(f"{name}: {med} bytes/frame ours {ours:.0f} apitrace {theirs:.0f}", file=sys.stderr)

    print(f"Frames per second (median of {a.repeats} interleaved runs of {a.frames} frames, first 10 skipped), "
          "Mesa llvmpipe under Xvfb, 2 cores.\n")
    print("| program | native fps | shim, no consumer | capturing to file | apitrace trace | capture / native | "
          "apitrace / native | bytes/frame glcast | bytes/frame apitrace |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, m, ours, theirs in rows:
        print(f"| {name} | {m['native']:.0f} | {m['shim']:.0f} | {m['capture']:.0f} | {m['apitrace']:.0f} | "
              f"{m['capture'] / m['native']:.2f} | {m['apitrace'] / m['native']:.2f} | {ours:,.0f} | {theirs:,.0f} |")


if __name__ == "__main__":
    main()
