#!/usr/bin/env python3
"""Replay speed and memory: frames per second of `glcast replay --backend egl` against the
program's own frames per second on the same Mesa, and peak RSS of each. One run, the two
measurements interleaved, medians of R repeats. Writes a markdown table to stdout.

    bench/replay_bench.py BUILD_DIR [--frames N] [--repeats R]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "e2e"))
from xvfb import Xvfb  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
RSS = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
       "sys.stderr.write(r.stderr); sys.stdout.write(r.stdout); "
       "print('maxrss_kb', resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, file=sys.stderr)")


def measured(cmd, env):
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-c", RSS] + cmd, env=env, capture_output=True, text=True, timeout=900)
    wall = time.monotonic() - t0
    rss = int(re.search(r"maxrss_kb (\d+)", r.stderr).group(1))
    return r, wall, rss


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    glcast, shim = os.path.join(build, "glcast"), os.path.join(build, "libglcast.so")
    apps = os.path.join(build, "tests", "apps")
    tmp = tempfile.mkdtemp(prefix="glcast-replay-bench-")
    counter = os.path.join(tmp, "frame_counter.so")
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", counter, os.path.join(HERE, "frame_counter.c"), "-ldl"],
                   check=True)
    n = a.frames
    programs = {
        "glxgears": ["glxgears"],
        "ff_scene": [os.path.join(apps, "ff_scene"), "--frames", str(n + 20)],
        "core_scene": [os.path.join(apps, "core_scene"), "--frames", str(n + 20)],
        "glfw_dynamic": [os.path.join(apps, "glfw_dynamic"), "--frames", str(n + 20)],
        "xscreensaver gears (EGL)": ["/usr/libexec/xscreensaver/gears", "-window", "-delay", "0"],
    }
    rows = []
    with Xvfb():
        for name, cmd in programs.items():
            if "/" in cmd[0] and not os.path.exists(cmd[0]):
                continue
            capture = os.path.join(tmp, "c.glcs")
            subprocess.run([glcast, "capture", "-o", capture, "--frames", str(n), "--"] + cmd,
                           capture_output=True, timeout=900, check=True)
            native_fps, replay_fps, native_rss, replay_rss = [], [], [], []
            for _ in range(a.repeats):
                # the program: frames 10..n timed by the frame counter, like the replay below
                r, _, rss = measured(cmd, dict(os.environ, LD_PRELOAD=counter, FRAME_COUNTER_EXIT=str(n)))
                m = re.search(r"frame_counter: (\d+) frames in ([\d.]+) s", r.stderr)
                if m:
                    native_fps.append(int(m.group(1)) / float(m.group(2)))
                native_rss.append(rss)
                env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
                r, wall, rss = measured([glcast, "replay", capture, "--backend", "egl"], env)
                # the replay includes startup and frame 0 (context creation, uploads): subtract
                # the time of replaying frame 0 alone
                _, wall0, _ = measured([glcast, "replay", capture, "--backend", "egl", "--frames", "0:0"], env)
                replay_fps.append((n - 1) / max(wall - wall0, 1e-6))
                replay_rss.append(rss)
            rows.append((name, statistics.median(native_fps) if native_fps else float("nan"),
                         statistics.median(replay_fps), statistics.median(native_rss), statistics.median(replay_rss)))
            print(name, rows[-1], file=sys.stderr)
    print(f"Replay of {n}-frame captures on EGL (llvmpipe) without X, against the program under Xvfb; "
          f"medians of {a.repeats} interleaved runs.\n")
    print("| program | program fps | replay fps | replay / program | program peak RSS | replay peak RSS |")
    print("|---|---|---|---|---|---|")
    for name, nf, rf, nr, rr in rows:
        print(f"| {name} | {nf:.0f} | {rf:.0f} | {rf / nf:.2f} | {nr / 1024:.0f} MiB | {rr / 1024:.0f} MiB |")


if __name__ == "__main__":
    main()
