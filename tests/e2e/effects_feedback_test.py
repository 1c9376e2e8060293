#!/usr/bin/env python3
"""Effects never feed back: a program that never clears (tests/apps_extra/live_state.c
render_once: each frame draws over the last, flat) replayed with falling snow (snow.without_view=1:
a flat picture gets none by default). The passes decorate
what is presented; the program's next frame must draw over its own picture, so the pixels the
snow changes stay as many as one frame of snow changes, instead of piling up frame after frame.

    effects_feedback_test.py     with GLCAST, GLCAST_SHIM, APPS_DIR, OUT_DIR in the environment
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
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "effects_feedback")
FRAMES = 90


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def difference(a, b):
    """The mean absolute difference of two frames, in colour levels per channel."""
    (w, h, pa), (_, _, pb) = read_png(a), read_png(b)
    total = sum(abs(u - v) for ra, rb in zip(pa, pb) for x, y in zip(ra, rb) for u, v in zip(x, y))
    return total / (w * h * 3)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    capture = os.path.join(OUT, "render_once.glcs")
    program = [os.path.join(APPS, "live_state"), "render_once", "--size", "160x120",
               "--frames", str(FRAMES)]
    with Xvfb():
        r = subprocess.run([GLCAST, "capture", "-o", capture, "--"] + program, capture_output=True, text=True,
                           timeout=300)
    check(r.returncode == 0, f"capture failed: {r.stderr[-2000:]}")
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    for name, extra in (("plain", []), ("snow", ["--effects", "snow", "--effect-param", "snow.without_view=1"])):
        r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", os.path.join(OUT, name)] + extra,
                           capture_output=True, text=True, timeout=300, env=headless)
        check(r.returncode == 0, f"replay {name} failed: {r.stderr[-2000:]}")
    counts = [difference(os.path.join(OUT, "plain", f"frame-{k:06d}.png"), os.path.join(OUT, "snow", f"frame-{k:06d}.png"))
              for k in range(FRAMES)]
    early, late = max(counts[5:15]), max(counts[-10:])
    print(f"mean difference the snow makes, in levels: frames 5-14 at most {early:.2f}, last 10 frames at most "
          f"{late:.2f}; all: {' '.join(f'{c:.1f}' for c in counts)}")
    check(early > 0.1, "the snow changed nothing: the test shows nothing")
    check(late <= 1.5 * early, f"the snow piles up: a mean difference of {late:.2f} levels at the end against "
                               f"{early:.2f} early on")


if __name__ == "__main__":
    main()
    print("PASS")
