#!/usr/bin/env python3
"""A redraw culls what the program culled (docs/effects.md, "How redraw works"): ff_scene
--culled draws a quad facing away from the eye over the lower half of the view with back faces
culled, so the program never shows it, then turns culling off for its last draws (as neverball
culls its level and draws its menu without culling). With shadows and cover its frames must come
out as ff_scene's. Before, the passes' redraws ran with the frame's last culling state (off): the
quad hid the ground from the cover's normals and the shadows' re-rendered depth, and 36,003 of
76,800 pixels differed (the lower half without snow or shadows).

    redraw_culling_test.py     with GLCAST, APPS_DIR, OUT_DIR in the environment
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
OUT = os.path.join(os.environ.get("OUT_DIR", "/tmp/glcast-e2e"), "redraw_culling")
W, H = 320, 240


def main():
    shutil.rmtree(OUT, ignore_errors=True)
    os.makedirs(OUT)
    headless = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    images = {}
    with Xvfb():
        for name, extra in (("plain", []), ("culled", ["--culled"])):
            capture = os.path.join(OUT, f"{name}.glcs")
            r = subprocess.run([GLCAST, "capture", "-o", capture, "--", os.path.join(APPS, "ff_scene"), *extra,
                                "--size", f"{W}x{H}", "--frames", "2"], capture_output=True, text=True, timeout=300)
            if r.returncode != 0:
                raise AssertionError(f"capture {name} failed: {r.stderr[-2000:]}")
            for effects in ("", "shadows,cover"):
                out = os.path.join(OUT, f"{name}-{effects or 'none'}")
                r = subprocess.run([GLCAST, "replay", capture, "--backend", "egl", "--out", out] +
                                   (["--effects", effects] if effects else []),
                                   capture_output=True, text=True, timeout=300, env=headless)
                if r.returncode != 0:
                    raise AssertionError(f"replay {out} failed: {r.stderr[-2000:]}")
                images[name, effects] = read_png(os.path.join(out, "frame-000001.png"))[2]

    def off(a, b):
        return sum(1 for y in range(H) for x in range(W) if max(abs(p - q) for p, q in zip(a[y][x], b[y][x])) > 2)

    if off(images["plain", ""], images["culled", ""]):
        raise AssertionError("the culled quad shows in the program's own picture: the test is wrong")
    changed = off(images["plain", ""], images["plain", "shadows,cover"])
    unlike = off(images["plain", "shadows,cover"], images["culled", "shadows,cover"])
    print(f"the passes changed {changed} of {W * H} pixels; with the culled quad, {unlike} pixels more than 2 "
          "levels off")
    if changed < W * H // 3:
        raise AssertionError(f"the passes changed only {changed} pixels")
    if unlike > W * H // 1000:
        raise AssertionError(f"with a quad the program culled, {unlike} pixels differ: the redraw drew it")


if __name__ == "__main__":
    main()
    print("PASS")
