#!/usr/bin/env python3
"""Multisampling as the program asked for it (glcast.context_format): tests/apps_extra/multisample.c
asks for a 4-sample GLX window. The EGL backend renders into a 4-sample pbuffer and replays its
frames pixel-identically (before, single-sampled, every frame differed along the edges); OSMesa
has no multisampled framebuffer: it says so, and differs along polygon edges only.

    multisample_test.py     with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment
"""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png import read_png  # noqa: E402
from xvfb import Xvfb  # noqa: E402

GLCAST = os.environ["GLCAST"]
APPS = os.environ.get("APPS_DIR", "")
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "multisample")
FRAMES, W, H = 10, 320, 240


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    capture, own = os.path.join(OUT, "multisample.glcs"), os.path.join(OUT, "program")
    with Xvfb():
        r = subprocess.run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "multisample"), "--size",
                            f"{W}x{H}", "--frames", str(FRAMES)], capture_output=True, text=True, timeout=300,
                           env=dict(os.environ, GLCAST_SNAPSHOT_DIR=own))
    check(r.returncode == 0, f"capture failed: {r.stdout} {r.stderr[-2000:]}")
    check("GL_SAMPLES 4" in r.stdout, f"the program did not get 4 samples: {r.stdout}")
    dump = subprocess.run([GLCAST, "dump", capture], capture_output=True, text=True, timeout=120).stdout
    check("glcast.context_format(" in dump and "samples = 4" in dump, "the stream does not say the samples")
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--compare", own], capture_output=True,
                       text=True, timeout=300, env=headless)
    check(r.returncode == 0 and f"compared {FRAMES} frames: 0 differ" in r.stdout, f"egl: {r.stdout} {r.stderr}")
    osmesa = os.path.join(OUT, "osmesa")
    r = subprocess.run([GLCAST, "replay", capture, "--backend", "osmesa", "--out", osmesa], capture_output=True,
                       text=True, timeout=300, env=headless)
    check(r.returncode == 0 and "no multisampled framebuffer" in r.stderr, f"osmesa: {r.stdout} {r.stderr}")
    worst = 0
    for k in range(FRAMES):
        f = f"frame-{k:06d}.png"
        _, _, a = read_png(os.path.join(own, f))
        _, _, b = read_png(os.path.join(osmesa, f))
        worst = max(worst, sum(1 for ra, rb in zip(a, b) for p, q in zip(ra, rb) if p != q))
    check(worst < W * H // 100, f"osmesa differs in {worst} pixels of a frame: more than the edges")
    print(f"egl: {FRAMES} frames pixel-identical with 4 samples; osmesa (one sample): at most {worst} of {W * H} "
          f"pixels a frame differ, along the edges")


if __name__ == "__main__":
    main()
    print("PASS")
