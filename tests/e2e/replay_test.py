#!/usr/bin/env python3
"""Pixel-exact replay: a program is captured under Xvfb with GLCAST_SNAPSHOT_DIR (its own frames,
read before each swap), then replayed headless on EGL and on OSMesa; every frame must be
identical to the program's. A third replay keeps objects of its own first (--offset-names), so
its names differ from the master's: the name maps must make up for it. A fourth runs --verify:
the calls that only answered the program are executed too and must answer the same.

    replay_test.py CASE     with GLCAST, APPS_DIR, OUT_DIR in the environment
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "replay")

CASES = {
    "ff_scene": (lambda: [os.path.join(APPS, "ff_scene"), "--frames", "12"], 12),
    "core_scene": (lambda: [os.path.join(APPS, "core_scene"), "--frames", "12"], 12),
    "glfw_dynamic": (lambda: [os.path.join(APPS, "glfw_dynamic"), "--frames", "12"], 12),
    "glxgears": (lambda: ["glxgears"], 20),
    "xscreensaver_gears": (lambda: ["/usr/libexec/xscreensaver/gears", "-window"], 12),
    "threads_buffers": (lambda: [os.path.join(APPS, "threads_buffers"), "--frames", "6"], None),
    "fbo_ext": (lambda: [os.path.join(APPS, "fbo_ext"), "--frames", "8"], 8),
    "viewport_array": (lambda: [os.path.join(APPS, "viewport_array"), "--frames", "8"], 8),
    "client_draws": (lambda: [os.path.join(APPS, "client_draws"), "--frames", "8"], 8),
    "api_errors": (lambda: [os.path.join(APPS, "api_errors"), "--frames", "4"], 4),
    "window_bits": (lambda: [os.path.join(APPS, "window_bits"), "--frames", "4"], 4),
}


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=600, **kw)


def main(case):
    program, frames = CASES[case]
    out = os.path.join(OUT, case)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    capture, reference = os.path.join(out, "capture.glcs"), os.path.join(out, "program")
    limit = ["--frames", str(frames)] if frames else []
    with Xvfb():
        r = run([GLCAST, "capture", "-o", capture] + limit + ["--"] + program(),
                env=dict(os.environ, GLCAST_SNAPSHOT_DIR=reference))
    if r.returncode != 0:
        raise AssertionError(f"capture failed: {r.stderr[-2000:]}")
    n = len(os.listdir(reference))
    if n < (frames or 2):
        raise AssertionError(f"only {n} reference frames")
    # headless from here on: no DISPLAY
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    for backend, extra in (("egl", []), ("osmesa", []), ("egl", ["--offset-names", "5"]), ("osmesa", ["--verify"])):
        r = run([GLCAST, "replay", capture, "--backend", backend, "--compare", reference,
                 "--out", os.path.join(out, backend + "".join(extra))] + extra, env=env)
        print(f"{backend} {' '.join(extra)}: {r.stdout.strip()}")
        if r.returncode != 0:
            raise AssertionError(f"replay on {backend} {extra} differs from the program:\n{r.stdout[-3000:]}\n{r.stderr[-2000:]}")
        if "--verify" in extra and not re.search(r"verified \d+ replies: 0 differ", r.stdout):
            raise AssertionError(f"--verify found differences: {r.stdout}")
        m = re.search(r"compared (\d+) frames: 0 differ, 0 without reference", r.stdout)
        if not m or int(m.group(1)) != n:
            raise AssertionError(f"not every frame compared: {r.stdout}")
    with Xvfb():  # the window backend shows the frames in a GLFW window
        r = run([GLCAST, "replay", capture, "--backend", "window", "--compare", reference])
    print(f"window: {r.stdout.strip()}")
    if r.returncode != 0 or not re.search(rf"compared {n} frames: 0 differ", r.stdout):
        raise AssertionError(f"replay in a window differs:\n{r.stdout[-3000:]}\n{r.stderr[-2000:]}")
    print("PASS")


if __name__ == "__main__":
    main(sys.argv[1])
