#!/usr/bin/env python3
"""A program whose camera cannot be found is shown as it drew itself, under every pass.

The ring of pillars projected by its shader program as an equidistant fisheye (pillars --shader
--fisheye: not linear, as a planetarium projects its sky; no matrix holds a perspective
projection), with a HUD panel over it. No pass can tell its scene from its interface: replayed
with snow, rain, cover and shadows, every pixel of every frame equals the plain replay, and the
slave says why once. Before, the snow's spectral layer fell over the whole picture, the HUD
included (the interfaces of a planetarium, of a 2D menu).

    no_view_test.py     with GLCAST, APPS_DIR, OUT_DIR in the environment
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
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "no_view")
HUD = (230, 50, 40)  # pillars.c --hud


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    capture = os.path.join(OUT, "fisheye.glcs")
    with Xvfb():
        r = subprocess.run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "pillars"), "--shader", "--hud",
                            "--fisheye", "--size", "400x300", "--frames", "3"], capture_output=True, text=True, timeout=300)
    check(r.returncode == 0, f"capture failed: {r.stderr[-2000:]}")
    frames = [f"frame-{i:06d}.png" for i in range(3)]
    outputs = {}
    for name, effects in (("plain", None), ("snow", "snow"), ("rain", "rain"), ("cover", "cover"),
                          ("shadows", "shadows"), ("all", "snow,cover,icicles,shadows")):
        out = os.path.join(OUT, name)
        r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", out] +
                           (["--effects", effects] if effects else []),
                           capture_output=True, text=True, timeout=300, env=headless)
        check(r.returncode == 0, f"replay {name} failed: {r.stderr[-2000:]}")
        outputs[name] = r.stderr
    w, h, plain = read_png(os.path.join(OUT, "plain", frames[1]))
    hud = sum(1 for y in range(h) for x in range(w) if tuple(plain[y][x][:3]) == HUD)
    check(hud > 0.04 * w * h, f"the HUD shows in {hud} pixels only")
    for name in ("snow", "rain", "cover", "shadows", "all"):
        differ = 0
        for frame in frames:
            _, _, a = read_png(os.path.join(OUT, "plain", frame))
            _, _, b = read_png(os.path.join(OUT, name, frame))
            differ += sum(1 for y in range(h) for x in range(w) if a[y][x][:3] != b[y][x][:3])
        print(f"{name}: {differ} pixels differ from the plain replay in {len(frames)} frames")
        check(differ == 0, f"{name} changed {differ} pixels of a picture without a camera (the HUD's {hud} among them)")
    said = outputs["all"].count("no draw with a perspective projection")
    check(said == 1, f"the slave says {said} times that it found no camera:\n{outputs['all'][-2000:]}")
    print("no camera found: every pass leaves the picture as the program drew it")


if __name__ == "__main__":
    main()
